#!/usr/bin/env bash
# Throughput of a prebuilt tswm on this machine: GPU against the all-core
# CPU path, uniform and heterogeneous lanes, 10^5, 10^6 and 10^7 lanes.
# Needs only the binary (no Rust toolchain) and bash, awk, nproc.
#
#   benches/device/run.sh [TSWM] [OUTDIR]
#
# TSWM defaults to target/release/tswm (built elsewhere: `cargo build
# --release`), OUTDIR to ./device-bench. Writes OUTDIR/results.md (a
# table for docs/performance.md) and OUTDIR/log.txt. SIZES (default
# "100000 1000000 10000000") picks the lane counts, MAX_LANES (default
# 10000000) stops below 10^7; BACKENDS (default "gpu:f32 gpu:f64 cpu",
# BACKEND:PRECISION) picks the backends.
#
# "integration" is `tswm bench`: lanes generated, integrated, the GPU rows
# checked (and untrusted ones recomputed), nothing written. "end to end"
# is `tswm run --no-report`: the same plus lanes.csv and summary.csv on
# disk (in OUTDIR/scratch, removed after each run).
#   uniform: paper-like lanes (the paper's design, load from -6 to +6 kN,
#            2 s), as sweeps/million.toml;
#   heterogeneous: sweeps/heterogeneous.toml's draws (t_end 0.2 to 7.8 s,
#            lead angle 2 to 24 deg, load +-8 kN), N lanes.
set -euo pipefail
tswm=${1:-target/release/tswm}
out=${2:-device-bench}
max=${MAX_LANES:-10000000}
# BACKEND:PRECISION, or BACKEND (precision auto).
backends=${BACKENDS:-gpu:f32 gpu:f64 cpu}
mkdir -p "$out/scratch"
log=$out/log.txt
: >"$log"
export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-/tmp}

sweep() { # kind n -> file
  local f=$out/scratch/$1-$2.toml
  case $1 in
    uniform) printf '[[grid]]\nparam = "f2"\nfrom = -6000.0\nto = 6000.0\nn = %s\n' "$2" >"$f" ;;
    heterogeneous) printf '[base]\nt_end = 4.0\ngamma_deg = 13.0\nf2 = 0.0\n[sampling]\nmethod = "monte_carlo"\nn = %s\nseed = 2026\n[[tolerance]]\nparam = "t_end"\ndist = "uniform"\ntol = 3.8\n[[tolerance]]\nparam = "gamma_deg"\ndist = "uniform"\ntol = 11.0\n[[tolerance]]\nparam = "f2"\ndist = "uniform"\ntol = 8000.0\n' "$2" >"$f" ;;
  esac
  echo "$f"
}

rate() { # the lanes/s of a tswm summary line: its first figure, the whole
  # command's (a line where writing set the pace names the integration's
  # rate after it, which is not the end-to-end figure)
  sed -n 's/^tswm[^(]*(\([0-9]*\) lanes\/s.*/\1/p' | head -1
}

{
  echo "# tswm device benchmark, $(date -u +%Y-%m-%dT%H:%MZ)"
  echo
  echo "- binary: $("$tswm" --version)"
  echo "- CPU: $(nproc) threads, $(awk -F': ' '/model name/ {print $2; exit}' /proc/cpuinfo)"
  if command -v nvidia-smi >/dev/null; then
    echo "- GPU: $(nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader | head -1)"
  fi
  echo "- adapters (tswm devices):"
  "$tswm" devices 2>&1 | sed 's/^/    /'
  echo
  echo "| lanes | kind | backend | integration (lanes/s) | end to end (lanes/s) |"
  echo "|---|---|---|---|---|"
} >"$out/results.md"

for n in ${SIZES:-100000 1000000 10000000}; do
  [ "$n" -le "$max" ] || continue
  for kind in uniform heterogeneous; do
    f=$(sweep "$kind" "$n")
    for b in $backends; do
      be=${b%%:*}
      pr=auto
      [ "$be" = "$b" ] || pr=${b#*:}
      k=$("$tswm" bench "$f" --backend "$be" --precision "$pr" 2>>"$log" | tee -a "$log" | rate)
      e=$("$tswm" run "$f" --backend "$be" --precision "$pr" --no-report --out "$out/scratch/run" 2>>"$log" | tee -a "$log" | rate)
      rm -rf "$out/scratch/run"
      echo "| $n | $kind | $b | ${k:-failed} | ${e:-failed} |" | tee -a "$out/results.md"
    done
  done
done
rm -rf "$out/scratch"
echo "wrote $out/results.md"
