#!/bin/bash
# What a user's `tswm run` gets beside what the integrator does: medians
# of three whole-process runs (wall time) of `tswm bench`, `tswm run`
# (CSV and Parquet, report included) and `tswm report`, with their ratios
# to `tswm bench`, for
#   - 10^6 cheap lanes (t_end = 1e-4 s, the load swept) on all threads;
#   - 150,000 paper-like lanes (2 s of motion) on one thread of one core,
#     from the sweep and from a lane table (`--lanes`).
# Usage: benches/end_to_end/run.sh [TSWM] [WORKDIR]
# (also prints whether a software GPU is present: with one, `auto` runs a
# trial on it first, in `tswm bench` and `tswm run` alike)
set -euo pipefail
T=$(realpath "${1:-target/release/tswm}")
W=${2:-$(mktemp -d)}
mkdir -p "$W"
cd "$W"

cat > cheap.toml <<'TOML'
[base]
t_end = 1e-4
[[grid]]
param = "f2"
from = -5000.0
to = 5000.0
n = 1000000
TOML
cat > paper150k.toml <<'TOML'
[[grid]]
param = "f2"
from = -6000.0
to = 6000.0
n = 150000
TOML
python3 -c "
n = 150000
print('f2')
for i in range(n):
    print(repr(-6000.0 + 12000.0 * i / (n - 1)))
" > paper150k.csv

# median of three wall times of a command (its output folders removed first)
median() {
  local ts=()
  for _ in 1 2 3; do
    rm -rf out
    local s e
    s=$(date +%s.%N)
    "$@" > /dev/null 2>&1
    e=$(date +%s.%N)
    ts+=("$(echo "$e - $s" | bc -l)")
  done
  printf '%s\n' "${ts[@]}" | sort -g | sed -n 2p
}
ratio() { printf '%.2f' "$(echo "$1 / $2" | bc -l)"; }
row() { printf '| %s | %.2f s | %sx |\n' "$1" "$2" "$(ratio "$2" "$3")"; }

echo "tswm end to end on $(nproc) threads of: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"
echo "GPU adapters: $("$T" devices 2>/dev/null | sed -n 2p | cut -c1-60)"
echo
echo "| 10^6 cheap lanes, all threads | median wall | / tswm bench |"
echo "|---|---|---|"
b=$(median "$T" bench cheap.toml)
row "tswm bench" "$b" "$b"
c=$(median "$T" run cheap.toml --out out)
row "tswm run (lanes.csv, summary.csv, report)" "$c" "$b"
p=$(median "$T" run cheap.toml --out out --format parquet)
row "tswm run --format parquet" "$p" "$b"
rm -rf csv pq
"$T" run cheap.toml --out csv > /dev/null 2>&1
"$T" run cheap.toml --out pq --format parquet > /dev/null 2>&1
r=$(median "$T" report pq)
row "tswm report (Parquet folder)" "$r" "$b"
r=$(median "$T" report csv)
row "tswm report (CSV folder)" "$r" "$b"
echo
# Where a software GPU (Mesa's lavapipe) is installed, both commands above
# first run the backend choice's trial on it (`auto`); the same with the
# CPU path named, no trial in either:
echo "| the same, --backend cpu (no trial) | median wall | / tswm bench |"
echo "|---|---|---|"
b=$(median "$T" bench cheap.toml --backend cpu)
row "tswm bench --backend cpu" "$b" "$b"
c=$(median "$T" run cheap.toml --out out --backend cpu)
row "tswm run --backend cpu" "$c" "$b"
p=$(median "$T" run cheap.toml --out out --format parquet --backend cpu)
row "tswm run --format parquet --backend cpu" "$p" "$b"
echo
echo "| 150,000 paper-like lanes, 1 thread on 1 core | median wall | / tswm bench |"
echo "|---|---|---|"
one="taskset -c 0"
b=$(median $one "$T" bench paper150k.toml --threads 1)
row "tswm bench" "$b" "$b"
r=$(median $one "$T" run paper150k.toml --threads 1 --out out)
row "tswm run (CSV and report)" "$r" "$b"
bl=$(median $one "$T" bench --lanes paper150k.csv --threads 1)
row "tswm bench --lanes" "$bl" "$bl"
rl=$(median $one "$T" run --lanes paper150k.csv --threads 1 --out out)
row "tswm run --lanes" "$rl" "$bl"
