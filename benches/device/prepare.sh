#!/usr/bin/env bash
# Prepares the one-call GPU check for a lent GPU machine, from the
# project's root:
#
#   bash benches/device/prepare.sh
#
# Builds the release binary and the test binaries, strips them into
# .device/ (the full binary is over the 64 MiB a device call carries),
# copies benches/device/on-device.sh
# and benches/device/run.sh beside it, fetches the Vulkan and EGL loader
# packages into .gl/ (a GPU image may have the NVIDIA driver but no
# loader), keeps both folders out of git, and prints the call to make.
set -euo pipefail
[ -f Cargo.toml ] || { echo "run from the project's root"; exit 2; }
cargo build --release --quiet
mkdir -p .device .gl
# Keep both folders out of git where this is a git checkout (a worktree's
# or a submodule's exclude file is not at .git/info/exclude; an exported
# tree has none).
if exclude="$(git rev-parse --git-path info/exclude 2>/dev/null)"; then
  mkdir -p "$(dirname "$exclude")"
  for d in /.device/ /.gl/; do
    grep -qxF "$d" "$exclude" 2>/dev/null || echo "$d" >> "$exclude"
  done
fi
strip -o .device/tswm target/release/tswm
# The test binaries whose GPU tests the device script runs: the
# integration tests (the f64 shader functions) and the library's unit
# tests (the mirrored functions), stripped (together about 60 MB with
# the binary, under the 64 MiB a call carries).
for t in $(cargo test --release --no-run --message-format=json 2>/dev/null |
  python3 -c 'import sys, json
for l in sys.stdin:
    j = json.loads(l)
    if j.get("executable") and j.get("profile", {}).get("test"):
        print(("it-tests" if j["target"]["name"] == "it" else "lib-tests") + "=" + j["executable"])'); do
  case "$t" in
    it-tests=*|lib-tests=*) strip -o ".device/${t%%=*}" "${t#*=}" ;;
  esac
done
cp benches/device/on-device.sh benches/device/run.sh .device/
o='-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=/tmp/amd64'
mkdir -p /tmp/amd64/partial
# shellcheck disable=SC2086
apt-get $o update -qq >/dev/null 2>&1 || true
# shellcheck disable=SC2086
(cd .gl && rm -f ./*.deb && apt-get $o download libvulkan1 libegl1 libglvnd0 libopengl0 libgl1 libglx0 libgles2 >/dev/null 2>&1) || true
ls .gl/*.deb >/dev/null 2>&1 || { echo "could not fetch the loader packages into .gl/"; exit 1; }
echo "prepared: .device/tswm ($(du -h .device/tswm | cut -f1)), $(ls .gl/*.deb | wc -l) loader packages in .gl/"
echo "on the GPU machine, from the project's root: bash .device/on-device.sh (carry .device and .gl; about 4 minutes on an H100)"
echo "then put its figures (devices.txt, check.txt, shader-tests.txt, bench/results.md, diffrax.txt under \$OUT) in docs/performance.md and docs/gpu.md"
