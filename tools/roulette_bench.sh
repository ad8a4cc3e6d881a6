#!/bin/bash
# Cost and variance of ratio and residual ratio tracking without Russian
# roulette and with thresholds 0.01 … 0.3, against density
# (docs/results/roulette/README.md, "Choosing the default").
#   tools/roulette_bench.sh [OUT_DIR]   (default docs/results/roulette/sweep)
cd "$(dirname "$0")/.."
out="${1:-docs/results/roulette/sweep}"
mkdir -p "$out"
E=track_length,ratio_tracking:roulette=0,residual_ratio_tracking:roulette=0
for t in 0.01 0.03 0.1 0.3; do
  E+=",ratio_tracking:roulette=$t,residual_ratio_tracking:roulette=$t"
done
for S in 1 10 100 1000 10000 100000 1000000; do
  echo "## sigma_t_scale $S"
  target/release/fogbank bench --resolution 64 --size 64 --frames 2 --threads 2 --estimators $E --sigma-t-scale $S --stats-size 0 --json "$out/cost_$S.json" 2>/dev/null
done
for S in 10 100 1000; do
  echo "## accuracy, sigma_t_scale $S"
  target/release/fogbank bench --resolution 64 --size 32 --frames 2 --threads 2 --estimators $E --sigma-t-scale $S --stats-size 32 --stats-frames 1024 --json "$out/accuracy_$S.json" 2>/dev/null
done
