"""Where a lane's cost goes: instruction counts of one `tswm` command under
callgrind, split by what the instructions do.

    python3 benches/cost_split.py [--tswm target/profiling/tswm] -- run --lanes lanes.csv --out o

runs `TSWM ARGS` (add `--threads 1 --backend cpu`: one thread, the CPU
path) under `valgrind --tool=callgrind`, and prints, for each part of the
work, its instructions per lane and its share. Instruction counts are
exact and repeatable (the same binary and input give the same counts on
any machine), which wall times on a shared machine are not; they are not
times (a division costs more than an addition), but a part that executes
fewer instructions for the same lanes has less to do.

Build the binary with line tables first (`cargo build --profile
profiling`): the split reads the source file each instruction was
compiled from, inlined code included, so the integrator's hot loop
(compiled as one function) is split by what each of its lines does.

The parts:
- right-hand side: the model's formulas (src/model) and the right-hand
  side (src/integrator/rhs.rs), the maths library;
- stages and step control: the tableau, the error norm, the step size
  (stepper.rs, control.rs, components.rs, settings.rs);
- step verdicts and error budget: how an attempt ends, the energy flow,
  the accuracy estimate (verdict.rs, flow.rs, accuracy.rs);
- events and the automaton: root location, the steps onto events, mode
  changes, start and end of a lane (events.rs, step.rs, automaton.rs,
  outcome.rs, result.rs);
- lockstep bookkeeping: the slots, the lanes' columns, what the standard
  library inlines into the integrator's loops (lockstep.rs, lanewise.rs,
  batch.rs, width.rs, backend);
- reading and checking lanes: the lane table or sweep, the parameters'
  checks and derived values (src/input, src/params, the CSV reader,
  number parsing);
- writing: lanes.csv and Parquet, statistics, the report (src/output,
  src/run, src/stats, src/report, number formatting);
- other: memory allocation and copies (malloc, memcpy, memset), start-up,
  threads.
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile
from collections import Counter

PARTS = [
    ("right-hand side", r"src/model/|src/integrator/rhs\.rs|libm\.so|/math/"),
    ("stages and step control",
     r"src/integrator/(stepper|control|components|settings)\.rs"),
    ("step verdicts and error budget", r"src/integrator/(verdict|flow|accuracy)\.rs"),
    ("events and the automaton",
     r"src/integrator/(events|step|automaton|outcome|result|path)\.rs"),
    ("lockstep bookkeeping",
     r"src/integrator/(lockstep|batch|width|mod)\.rs|src/lanewise\.rs|src/backend/"),
    ("reading and checking lanes", r"src/input/|src/params/|/csv-|/csv_core|dec2flt"),
    ("writing", r"src/output/|src/run/|src/stats/|src/report/|zmij|/arrow|/parquet"),
]
# Standard-library code is filed under the tswm function it was inlined
# into.
BY_FUNCTION = [
    ("lockstep bookkeeping", r"tswm::integrator::batch::|tswm::integrator::lockstep"),
    ("stages and step control", r"tswm::integrator::stepper::"),
    ("events and the automaton", r"tswm::integrator::(step|events|automaton)::"),
    ("reading and checking lanes",
     r"tswm::(input|params)::|csv::|csv_core::|dec2flt|trim_matches"),
    # zmij writes numbers as text; the sorts are the statistics' (quantiles,
    # rank correlations).
    ("writing", r"tswm::(output|run|stats|report)::|zmij|slice::sort::"),
]


def part_of(location):
    """The part an instruction's `file:function` belongs to."""
    file, _, function = location.partition(":")
    if "/library/" not in file:
        for name, pattern in PARTS:
            if re.search(pattern, file):
                return name
    for name, pattern in BY_FUNCTION:
        if re.search(pattern, function):
            return name
    for name, pattern in PARTS:
        if re.search(pattern, file):
            return name
    return "other"


def split(callgrind_out):
    """Instructions by part, from callgrind's per-file, per-function counts."""
    text = subprocess.run(
        ["callgrind_annotate", "--inclusive=no", "--auto=no", "--threshold=100", callgrind_out],
        capture_output=True, text=True, check=True).stdout
    total, parts = 0, Counter()
    rows = False
    for line in text.splitlines():
        if "file:function" in line:
            rows = True
            continue
        if rows and not line.strip():
            break  # the end of the table
        m = re.match(r"\s*([\d,]+)\s+(?:\([\s\d.%]+\)\s+)?(\S.*)$", line)
        if not rows or not m:
            continue
        n = int(m.group(1).replace(",", ""))
        loc = m.group(2).split(" [")[0]
        parts[part_of(loc)] += n
        total += n
    return total, parts


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tswm", default="target/profiling/tswm")
    ap.add_argument("--lanes-count", type=int, default=None,
                    help="lanes the command runs (default: the lane table's rows)")
    ap.add_argument("args", nargs=argparse.REMAINDER)
    a = ap.parse_args()
    args = a.args[1:] if a.args[:1] == ["--"] else a.args
    n = a.lanes_count
    if n is None and "--lanes" in args:
        with open(args[args.index("--lanes") + 1]) as f:
            n = sum(1 for _ in f) - 1
    if not n:
        sys.exit("give --lanes-count N (the lanes the command runs)")
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "callgrind.out")
        subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}",
                        a.tswm, *args], check=True, stdout=subprocess.DEVNULL,
                       stderr=subprocess.DEVNULL)
        total, parts = split(out)
    print(f"{n} lanes, {total / n:,.0f} instructions a lane")
    print("| part | instructions a lane | share |")
    print("|---|---|---|")
    for name, _ in PARTS + [("other", "")]:
        print(f"| {name} | {parts[name] / n:,.0f} | {100 * parts[name] / total:.1f} % |")


if __name__ == "__main__":
    main()
