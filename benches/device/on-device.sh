#!/usr/bin/env bash
# The one-call GPU check, run ON the lent machine from the project's root
# after benches/device/prepare.sh (which copies it to .device/):
#
#   bash .device/on-device.sh
#
# Writes into $OUT (default ./device-out): devices.txt (the adapters),
# check.txt (`tswm check` of the shipped map and a heterogeneous study:
# its verdict, per-column table and first disagreeing lanes), bench/
# (benches/device/run.sh: GPU against all CPU cores, integration and end
# to end) and diffrax.txt (the vmapped diffrax peer on the same GPU, when
# JAX is there). Sizes: SIZES (default "100000 1000000 10000000"),
# PEER_SIZES (default "100000 1000000"), CHECK (the sweeps checked).
# Exit status: 1 when a check fails its bounds, else 0.
set -u
OUT=${OUT:-./device-out}
mkdir -p "$OUT"
export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-/tmp}
here=$(cd "$(dirname "$0")" && pwd)
if ! ldconfig -p | grep -q libvulkan.so.1 && ls .gl/*.deb >/dev/null 2>&1; then
  for f in .gl/*.deb; do dpkg -x "$f" /; done
  ldconfig
fi
T=${TSWM:-$here/tswm}
icd=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
if ! "$T" devices 2>/dev/null | grep -qi nvidia && [ -f "$icd" ]; then
  export VK_DRIVER_FILES=$icd
  export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
fi
{
  date -u
  command -v nvidia-smi >/dev/null && nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader
  "$T" --version
  "$T" devices
} >"$OUT/devices.txt" 2>&1
cat "$OUT/devices.txt"
# 1. every GPU row against the f64 CPU path, the verdict kept (its first lines)
failed=0
for s in ${CHECK:-sweeps/efficiency_map.toml sweeps/heterogeneous.toml}; do
  for p in f32 f64; do
    echo "== tswm check $s --precision $p"
    timeout 200 "$T" check "$s" --precision "$p" >/tmp/tswm-check.txt 2>&1
    rc=$?
    head -n 40 /tmp/tswm-check.txt
    echo "exit status $rc"
    [ "$rc" = 0 ] || failed=1
  done
done >"$OUT/check.txt" 2>&1
cat "$OUT/check.txt"
# 1b. the shader's functions by what they compute on this GPU: its f64
# exp, pow and tan (tests/it/math64.rs) and the mirrored functions
# against the Rust ones (src/backend/gpu/mirrored/), from the test
# binaries prepare.sh strips beside the binary
{
  for t in "it-tests math64" "lib-tests mirrored"; do
    set -- $t
    if [ -x "$here/$1" ]; then
      echo "== $1 $2"
      TSWM_REQUIRE_GPU=1 timeout 120 "$here/$1" "$2" --nocapture 2>&1 |
        grep -E "f64 shader|worst|test result|panicked|differ|ulp" | sort -u
      [ "${PIPESTATUS[0]}" = 0 ] || failed=1
    else
      echo "== $1 not prepared (benches/device/prepare.sh strips it)"
    fi
  done
} >"$OUT/shader-tests.txt" 2>&1
cat "$OUT/shader-tests.txt"
# 2. throughput: GPU against all CPU cores
"$T" devices 2>/dev/null | grep -qiE 'nvidia|llvmpipe|amd|intel' && backends="gpu:f32 gpu:f64 cpu" || backends=cpu
SIZES=${SIZES:-100000 1000000 10000000} BACKENDS=${BACKENDS:-$backends} \
  timeout 300 bash "$here/run.sh" "$T" "$OUT/bench" >"$OUT/bench.log" 2>&1
tail -n 20 "$OUT/bench/results.md" 2>/dev/null || tail -n 20 "$OUT/bench.log"
# 3. the peer a JAX user would write, on the same GPU
if python3 -c 'import jax, diffrax' 2>/dev/null; then
  # shellcheck disable=SC2086
  timeout 150 python3 benches/peers/diffrax_peer.py ${PEER_SIZES:-100000 1000000} >"$OUT/diffrax.txt" 2>&1
else
  echo "diffrax peer skipped: python3 cannot import jax and diffrax here" >"$OUT/diffrax.txt"
fi
cat "$OUT/diffrax.txt"
exit "$failed"
