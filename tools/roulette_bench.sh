#!/bin/bash
# Cost of ratio and residual ratio tracking with and
# without Russian roulette against density (docs/results/roulette/README.md).
cd "$(dirname "$0")/.."
E=track_length,ratio_tracking,ratio_tracking:roulette=0.1,residual_ratio_tracking,residual_ratio_tracking:roulette=0.1
for S in 1 10 100 1000 10000 100000 1000000; do
  echo "## sigma_t_scale $S"
  target/release/fogbank bench --resolution 64 --size 64 --frames 2 --threads 2 --estimators $E --sigma-t-scale $S --stats-size 0 --json docs/results/roulette/cost_$S.json 2>/dev/null
done
for S in 10 100; do
  echo "## accuracy, sigma_t_scale $S"
  target/release/fogbank bench --resolution 64 --size 32 --frames 2 --threads 2 --estimators $E --sigma-t-scale $S --stats-size 32 --stats-frames 1024 --json docs/results/roulette/accuracy_$S.json 2>/dev/null
done
