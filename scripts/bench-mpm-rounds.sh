#!/bin/bash
# Interleaved MPM benchmark rounds (docs/performance.md, MPM section): for each round and
# binary, the needle and two-block cases (quadratic B-spline, MUSL, 1 and 2 threads) with
# OMP_WAIT_POLICY=passive and with the policy unset. Prints: binary policy benchmark rate.
# usage: scripts/bench-mpm-rounds.sh ROUNDS BENCH_BINARY...
if [ $# -lt 2 ] || ! [[ "$1" =~ ^[1-9][0-9]*$ ]]; then echo "usage: $0 ROUNDS(positive integer) BENCH_BINARY..." >&2; exit 2; fi
for b in "${@:2}"; do [ -x "$b" ] || { echo "$0: $b is not an executable bench_mpm" >&2; exit 2; }; done
R=$1; shift
F='(Needle|TwoBlocks)/bspline:1/musl:1'
for r in $(seq 1 $R); do
  for b in "$@"; do
    for pol in passive default; do
      if [ $pol = passive ]; then env OMP_WAIT_POLICY=passive $b --benchmark_min_time=1.5s --benchmark_filter="$F" 2>/dev/null | grep BM_ | awk -v b=$(basename $b) -v p=$pol '{for(i=1;i<=NF;i++) if($i ~ /particle_steps_per_s=/){split($i,a,"=");print b, p, $1, a[2]}}';
      else $b --benchmark_min_time=1.5s --benchmark_filter="$F" 2>/dev/null | grep BM_ | awk -v b=$(basename $b) -v p=$pol '{for(i=1;i<=NF;i++) if($i ~ /particle_steps_per_s=/){split($i,a,"=");print b, p, $1, a[2]}}'; fi
    done
  done
done
