"""Compares scipy_reference.py's output with tswm's lanes.csv:

    python3 compare.py REF.csv LANES.csv [ENGINEERING.csv]

Discrete fields (status, contact_end) must agree; x1, v1, the works and
the four mesh energies are compared relative to max(1, |value|).
"""
import csv, sys
ref=list(csv.DictReader(open(sys.argv[1])))
e1=list(csv.DictReader(open(sys.argv[2])))
e2=list(csv.DictReader(open(sys.argv[3]))) if len(sys.argv) > 3 else e1
worst=(0,'','')
over=0; differ=0
for r,a,b in zip(ref,e1,e2):
    if not (r['status']==a['status'] and r['contact_end']==a['contact_end']):
        differ+=1; print('differ', r['lane'], r['status'], r['contact_end'], a['status'], a['contact_end']); continue
    if r['status']!='ok': continue
    lw=0
    for k,src in [(k,a) for k in ['x1_end','v1_end','w_motor','w_load','w_friction']]+[(k,b) for k in ['w1_in','w1_out','w2_in','w2_out']]:
        d=abs(float(r[k])-float(src[k]))/max(1,abs(float(src[k])))
        lw=max(lw,d)
        if d>worst[0]: worst=(d,k,r['lane'])
    if lw>1e-6: over+=1
print(f'{len(ref)} lanes: discrete differ {differ}, lanes over 1e-6 {over}, worst {worst}')
