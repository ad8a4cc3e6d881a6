#!/usr/bin/env bash
# Jackknife's cost ratio on a real smoke plume: primary-ray transmittance
# of data/dragon.vdb (scenes/smoke.toml's view, 480×300, f16
# voxels, trilinear) per estimator and σ_t scale, render seconds and lookups
# per pixel sample, all in one run on this machine.
#   tools/jackknife_dragon.sh [FOGBANK] [SPP] > docs/results/jackknife_dragon.md
set -euo pipefail
cd "$(dirname "$0")/.."
fb=${1:-target/release/fogbank}
spp=${2:-64}
echo "| σ_t scale | track-length s (lookups) | ratio tracking s (lookups) | jackknife s (lookups) | jackknife / track-length | jackknife / ratio tracking |"
echo "|---|---|---|---|---|---|"
for s in 1 2 4 8 12 32 64; do
  row="| $s |"
  declare -A t
  for e in track_length ratio_tracking jackknife; do
    line=$("$fb" render scenes/smoke.toml --set integrator.type=transmittance \
      --set integrator.estimator=$e --set media.0.sigma_t_scale=$s --spp "$spp" \
      -o /tmp/jackknife_dragon.exr 2>&1 | grep -o 'spp .*sample')
    secs=$(echo "$line" | sed -E 's/.*\), ([0-9.]+) s.*/\1/')
    looks=$(echo "$line" | sed -E 's/.* ([0-9.]+) lookups.*/\1/')
    t[$e]=$secs
    row="$row $secs ($looks) |"
  done
  row="$row $(echo "scale=2; ${t[jackknife]} / ${t[track_length]}" | bc) | $(echo "scale=2; ${t[jackknife]} / ${t[ratio_tracking]}" | bc) |"
  echo "$row"
done
