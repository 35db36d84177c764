#!/bin/bash
# Thread scaling of the MPM step (docs/performance.md, "Thread scaling"): `bench_mpm --steps N
# --threads T` on the 49,500-point needle problem and on the same needle in a 1,008,000-point block
# (`--large`), T = 1, 2, 4, 8, 16; prints one table: problem, threads, M particle-steps/s (median
# step wall time), parallel efficiency (rate / (T x the 1-thread rate)) and the scatter's plan
# (imbalance of the block colouring: 1 = even shares; the bound on the scatter's speed-up).
# Then the phases of the large problem's step (bench_mpm --phases: wall ms per step, share, CPU/wall)
# at 1 thread and at the largest thread count. About 1.5 min on a 16-core machine (STEPS 200,
# LARGE_STEPS 20); each of the 12 runs is cut at 22 s and at what is left of a 150 s budget (BUDGET_S),
# so the script ends within about 150 s whatever happens (a run cut short prints 'failed', one
# past the budget 'skipped').
# usage: scripts/mpm_scaling.sh [BENCH_MPM]
#   BENCH_MPM: a bench_mpm binary (default .devcarry/bin/bench_mpm if present, else
#   build/release/bench/bench_mpm). Environment: STEPS, LARGE_STEPS, THREADS ("1 2 4 8 16");
#   OMP_* settings (OMP_PROC_BIND, OMP_WAIT_POLICY) pass through and are printed.
set -u
B=${1:-}
if [ -z "$B" ]; then
  if [ -x .devcarry/bin/bench_mpm ]; then B=.devcarry/bin/bench_mpm; else B=build/release/bench/bench_mpm; fi
fi
[ -x "$B" ] || { echo "$0: $B is not an executable bench_mpm (build it: cmake --build --preset release --target bench_mpm)" >&2; exit 2; }
STEPS=${STEPS:-200}
LARGE_STEPS=${LARGE_STEPS:-20}
THREADS=${THREADS:-"1 2 4 8 16"}
BUDGET_S=${BUDGET_S:-150}
for v in "$STEPS" "$LARGE_STEPS" "$BUDGET_S" $THREADS; do
  [[ "$v" =~ ^[1-9][0-9]*$ ]] || { echo "$0: STEPS, LARGE_STEPS, BUDGET_S and THREADS take positive integers, not '$v'" >&2; exit 2; }
done
# seconds a run may take: 22, or what is left of the budget (0: skip it)
cap() { local left=$((BUDGET_S - 2 - SECONDS)); ((left > 22)) && left=22; ((left < 2)) && left=0; echo $left; }
echo "# $B on $(nproc) CPUs ($(grep -m1 'model name' /proc/cpuinfo 2>/dev/null | cut -d: -f2 | sed 's/^ *//')), $(date -u '+%Y-%m-%d %H:%M UTC')"
echo "# $(env | grep '^OMP_' | tr '\n' ' ')load average $(cut -d' ' -f1-3 /proc/loadavg)"
# the topology: 16 CPUs may be 8 cores with two hardware threads each
command -v lscpu >/dev/null && echo "# $(lscpu | grep -E '^(Thread\(s\) per core|Core\(s\) per socket|Socket\(s\)|NUMA node\(s\)|L3 cache)' | sed 's/  */ /g' | tr '\n' ';')"
printf '%-28s %7s %12s %10s %10s\n' problem threads 'M steps/s' efficiency imbalance
for problem in needle large; do
  if [ $problem = needle ]; then args="--steps $STEPS"; name="needle, 49,500 points"; else
    args="--steps $LARGE_STEPS --large"; name="large, 1,008,000 points"; fi
  one=""
  for t in $THREADS; do
    c=$(cap)
    if [ "$c" = 0 ]; then printf '%-28s %7s %12s %10s %10s\n' "$name" "$t" skipped - -; continue; fi
    out=$(timeout "$c" "$B" $args --threads "$t" 2>&1)
    rate=$(sed -n 's/.*median [0-9.]* ms (\([0-9.]*\) M\/s).*/\1/p' <<<"$out")
    imb=$(sed -n 's/.*imbalance \([0-9.]*\).*/\1/p' <<<"$out")
    if [ -z "$rate" ]; then
      printf '%-28s %7s %12s %10s %10s\n' "$name" "$t" failed - -
      echo "$out" | tail -3 | sed 's/^/#   /'
      continue
    fi
    [ -z "$one" ] && [ "$t" = 1 ] && one=$rate
    eff=$(awk -v r="$rate" -v o="$one" -v t="$t" 'BEGIN { if (o == "") print "-"; else printf "%.0f %%", 100 * r / (t * o) }')
    printf '%-28s %7s %12s %10s %10s\n' "$name" "$t" "$rate" "$eff" "${imb:--}"
  done
done
last=1
for t in $THREADS; do last=$t; done
for t in $(printf '%s\n' 1 "$last" | sort -un); do
  echo "# phases of the large problem's step, $t thread(s): $B --steps $LARGE_STEPS --large --threads $t --phases"
  c=$(cap)
  if [ "$c" = 0 ]; then echo skipped; continue; fi
  out=$(timeout "$c" "$B" --steps "$LARGE_STEPS" --large --threads "$t" --phases 2>&1)
  if grep -q '^phases' <<<"$out"; then sed -n '/^phases/,$p' <<<"$out"; else echo "failed"; echo "$out" | tail -3 | sed 's/^/#   /'; fi
done
