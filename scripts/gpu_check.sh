#!/usr/bin/env bash
# One call on a GPU machine (CUDA toolkit with nvcc, CMake, Ninja; no package
# registry): builds the CUDA MPM plugin, runs the GPU agreement tests, times
# bench_mpm on the GPU at ~50k and ~4.2 M points (the sorted kernel, its
# variants and the naive one) and runs the quick example and the seed 000 local
# model (grid contact) through the CLI on the GPU and the CPU. Run from the repository root with prebuilt host programs
# in .devcarry/bin (needlesim, bench_mpm, test_gpu) and their shared libraries
# in .devcarry/lib (or packed in .devcarry/lib.tar.xz). Logs go to $OUT (default:
# .devcarry/out), 7 files. Under 6 minutes.
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
for v in "NEEDLESIM_MPM_CUDA_SPREAD=1" "NEEDLESIM_MPM_CUDA_MINBLOCKS=8" "NEEDLESIM_MPM_CUDA_TILE=1"; do
  echo "--- the agreement tests with $v"
  env "$v" timeout 60 "$BIN/test_gpu" --gtest_color=no --gtest_filter='Cases/GpuAgreement.*' 2>&1 | grep -E 'first 100|FAIL|PASSED' | tee -a "$OUT/gpu_tests.log"
done

section "bench_mpm on the GPU"
{
  # the sorted kernel (default: warp-level sums, then global atomics), its variants, the naive one
  for v in "X=" "NEEDLESIM_MPM_CUDA_SPREAD=1" "NEEDLESIM_MPM_CUDA_MINBLOCKS=8" "NEEDLESIM_MPM_CUDA_TILE=1"; do
    echo "--- 49.5k points, sorted, $v"
    env "$v" timeout 60 "$BIN/bench_mpm" --steps 200 --device cuda --kernel sorted
  done
  echo "--- 49.5k points, naive"
  timeout 60 "$BIN/bench_mpm" --steps 200 --device cuda --kernel naive
  for v in "X=" "NEEDLESIM_MPM_CUDA_SPREAD=1" "NEEDLESIM_MPM_CUDA_MINBLOCKS=8" "NEEDLESIM_MPM_CUDA_SORT_EVERY=32" \
           "NEEDLESIM_MPM_CUDA_SPREAD=1 NEEDLESIM_MPM_CUDA_MINBLOCKS=8"; do
    echo "--- 4.2 M points (--scale 4.4), sorted, $v (per-phase profile: events between the kernels)"
    env NEEDLESIM_MPM_CUDA_PROFILE=1 $v timeout 90 "$BIN/bench_mpm" --steps 40 --scale 4.4 --device cuda --kernel sorted
  done
  echo "--- 4.2 M points, naive (profile)"
  NEEDLESIM_MPM_CUDA_PROFILE=1 timeout 90 "$BIN/bench_mpm" --steps 40 --scale 4.4 --device cuda --kernel naive
  echo "--- 49.5k points, CPU, $(nproc) threads (reference)"
  timeout 60 "$BIN/bench_mpm" --steps 60 --threads "$(nproc)"
} 2>&1 | tee "$OUT/bench.log"

section "CLI: quick example (CPU, then GPU) and the local model with grid contact (GPU, then CPU)"
mk() {  # mk <example> <device> <out.yaml>: the example with model.mpm.device, grid contact, 4 CPU threads
  sed -e "s/^  mpm:$/  mpm:\n    device: $2\n    threads: 4\n    parting: none\n    contact: grid/" -e '/^    contact: cfemp/d' -e '/^    cfemp_element_size:/d' \
      -e '/^    threads: /d' "$1" > "$3"
}
{
  mk examples/mpm/quick_needle_block.yaml cpu "$WORK/quick_cpu.yaml"
  mk examples/mpm/quick_needle_block.yaml cuda "$WORK/quick_gpu.yaml"
  mk examples/mpm/local_model.yaml cuda "$WORK/local_grid_gpu.yaml"
  mk examples/mpm/local_model.yaml cpu "$WORK/local_grid_cpu.yaml"
  for s in quick_cpu quick_gpu local_grid_gpu local_grid_cpu; do
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
  python3 - "$WORK/res_local_grid_cpu/forces.csv" "$WORK/res_local_grid_gpu/forces.csv" <<'PY' || true
import csv, sys
def col(path):
    rows = list(csv.reader(l for l in open(path) if not l.startswith("#")))
    i = [k for k, h in enumerate(rows[0]) if h.startswith("force_total")][0]
    return [float(r[i]) for r in rows[1:]]
c, g = col(sys.argv[1]), col(sys.argv[2])
n = min(len(c), len(g))
peak = max(abs(x) for x in c[:n])
d = [abs(c[k] - g[k]) for k in range(n)]
touch = [k for k in range(n) if c[k] != 0][:10]
first = max([d[k] / max(abs(c[k]), 1e-3 * peak) for k in touch] or [0])
print(f"local model, grid contact: {len(c)} CPU rows, {len(g)} GPU rows, peak {peak:.4g} N; "
      f"the first 10 rows with contact within {first:.3g} relative; all rows within {max(d) / peak:.3g} of the peak")
PY
  cp "$WORK/res_local_grid_gpu/forces.csv" "$OUT/local_grid_gpu_forces.csv" 2>/dev/null
  cp "$WORK/res_local_grid_cpu/forces.csv" "$OUT/local_grid_cpu_forces.csv" 2>/dev/null
} 2>&1 | tee "$OUT/cli.log"

section "done"
return "$tests_rc"
}

main 2>&1 | tee "$LOG"
rc=${PIPESTATUS[0]}
rm -rf "$WORK"
echo "gpu_check: exit $rc (logs in $OUT)"
exit "$rc"
