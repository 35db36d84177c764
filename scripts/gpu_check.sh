#!/usr/bin/env bash
# One call on a GPU machine (CUDA toolkit with nvcc, CMake, Ninja; no package
# registry): builds the CUDA MPM plugin, runs the GPU agreement tests, times
# bench_mpm on the GPU at ~50k and ~4.2 M points (sorted and naive kernels) and
# runs the quick example and the seed 000 local model (grid contact) through
# the CLI on the GPU. Run from the repository root with prebuilt host programs
# in .devcarry/bin (needlesim, bench_mpm, test_gpu) and their shared libraries
# in .devcarry/lib (or packed in .devcarry/lib.tar.xz). Logs go to $OUT (default:
# .devcarry/out), at most 8 files. Under 6 minutes.
set -uo pipefail
ROOT=$(pwd)
CARRY=$ROOT/.devcarry
BIN=$CARRY/bin
OUT=${OUT:-$CARRY/out}
mkdir -p "$OUT"
LOG=$OUT/gpu_check.log
export LD_LIBRARY_PATH=$CARRY/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
export NEEDLESIM_MPM_CUDA_PLUGIN=$BIN/libneedlesim_mpm_cuda.so
export NEEDLESIM_SOURCE_DIR=$ROOT
WORK=$(mktemp -d /tmp/gpu_check.XXXXXX)
# The shared libraries may come packed (.devcarry/lib.tar.xz, to fit the carry limit).
if [ -f "$CARRY/lib.tar.xz" ]; then
  mkdir -p "$WORK/lib" && tar -C "$WORK/lib" -xJf "$CARRY/lib.tar.xz" && export LD_LIBRARY_PATH=$WORK/lib:$LD_LIBRARY_PATH
fi
t_start=$(date +%s)
section() { echo; echo "=== $* ($(( $(date +%s) - t_start )) s)"; }

main() {

section "machine"
date -u
nvidia-smi || echo "nvidia-smi failed"
nvcc --version || echo "nvcc not on PATH"
nproc
for f in needlesim bench_mpm test_gpu; do
  [ -x "$BIN/$f" ] || { echo "missing $BIN/$f (copy the host build there)"; return 1; }
done

section "plugin build (sm_90)"
if ! timeout 240 cmake -S src/needlesim/engines/mpm/cuda/plugin -B "$WORK/cu" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    > "$OUT/plugin_build.log" 2>&1 || ! timeout 240 ninja -C "$WORK/cu" >> "$OUT/plugin_build.log" 2>&1; then
  echo "PLUGIN BUILD FAILED: the last lines of $OUT/plugin_build.log:"
  tail -n 60 "$OUT/plugin_build.log"
  return 1
fi
cp "$WORK/cu/libneedlesim_mpm_cuda.so" "$BIN/" || return 1
ls -la "$BIN/libneedlesim_mpm_cuda.so"

section "GPU tests (test_gpu: label gpu)"
timeout 120 "$BIN/test_gpu" --gtest_color=no 2>&1 | tee "$OUT/gpu_tests.log" | grep -vE '^\[ +(RUN|OK) +\]' | tail -n 40
tests_rc=${PIPESTATUS[0]}
echo "test_gpu exit $tests_rc"

section "bench_mpm on the GPU"
{
  for k in sorted naive; do
    echo "--- 49.5k points, $k"
    timeout 60 "$BIN/bench_mpm" --steps 200 --device cuda --kernel $k
    echo "--- 4.2 M points (--scale 4.4), $k (with the per-phase profile: events between the kernels)"
    NEEDLESIM_MPM_CUDA_PROFILE=1 timeout 90 "$BIN/bench_mpm" --steps 40 --scale 4.4 --device cuda --kernel $k
  done
  echo "--- 4.2 M points, sorted, sorting every step"
  NEEDLESIM_MPM_CUDA_SORT_EVERY=1 timeout 90 "$BIN/bench_mpm" --steps 40 --scale 4.4 --device cuda --kernel sorted
  echo "--- 49.5k points, CPU, $(nproc) threads (reference)"
  timeout 60 "$BIN/bench_mpm" --steps 60 --threads "$(nproc)"
} 2>&1 | tee "$OUT/bench.log"

section "CLI: quick example (CPU, then GPU) and the local model with grid contact on the GPU"
mk() {  # mk <example> <device> <out.yaml>: the example with model.mpm.device and grid contact
  sed -e "s/^  mpm:$/  mpm:\n    device: $2/" -e '/^    contact: cfemp/d' -e '/^    cfemp_element_size:/d' \
      -e 's/^    threads: .*$//' "$1" > "$3"
}
{
  mk examples/mpm/quick_needle_block.yaml cpu "$WORK/quick_cpu.yaml"
  mk examples/mpm/quick_needle_block.yaml cuda "$WORK/quick_gpu.yaml"
  mk examples/mpm/local_model.yaml cuda "$WORK/local_grid_gpu.yaml"
  for s in quick_cpu quick_gpu local_grid_gpu; do
    echo "--- $s"
    /usr/bin/time -f "$s: %e s wall, %M kB" timeout 150 "$BIN/needlesim" run -q --overwrite -o "$WORK/res_$s" "$WORK/$s.yaml"
    echo "exit $?"
    python3 - "$WORK/res_$s/summary.json" <<'PY' || true
import json, sys
s = json.load(open(sys.argv[1]))
r = s.get("results", {})
def v(k):
    x = r.get(k)
    return x.get("value") if isinstance(x, dict) else x
print({k: v(k) for k in ("peak_force", "final_force", "final_depth", "steps", "particles")})
for n in s.get("notes", []):
    if "particle-steps" in n or "GPU" in n: print(n[:600])
print("device:", s.get("scenario", {}).get("model", {}).get("mpm", {}).get("device"))
PY
  done
  cp "$WORK/res_local_grid_gpu/forces.csv" "$OUT/local_grid_gpu_forces.csv" 2>/dev/null
  cp "$WORK/res_quick_gpu/forces.csv" "$OUT/quick_gpu_forces.csv" 2>/dev/null
  cp "$WORK/res_quick_cpu/forces.csv" "$OUT/quick_cpu_forces.csv" 2>/dev/null
} 2>&1 | tee "$OUT/cli.log"

section "done"
return "$tests_rc"
}

main 2>&1 | tee "$LOG"
rc=${PIPESTATUS[0]}
rm -rf "$WORK"
echo "gpu_check: exit $rc (logs in $OUT)"
exit "$rc"
