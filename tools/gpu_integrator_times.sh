#!/bin/bash
# Kernel time (`--stats` gpu_ms) of restir, point_mis, visopt and ament on the
# procedural cloud of scenes/restir_cloud.toml, two binaries side by side,
# two rounds (docs/results/gpu.md, "Shapes as occluders").
#   tools/gpu_integrator_times.sh BIN_A BIN_B [WIDTH HEIGHT]
set -u
A=$1; B=$2; W=${3:-960}; H=${4:-540}
S=scenes/restir_cloud.toml
P=tools/gpu_integrator_times.toml
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
run() { # bin label scene args...
  local bin=$1 lab=$2 sc=$3; shift 3
  if "$bin" render "$sc" -q --device gpu --set camera.width="$W" --set camera.height="$H" "$@" \
      -o "$OUT/p.exr" --stats "$OUT/p.json" > /dev/null 2>&1; then
    printf "%s %s\n" "$lab" "$(grep -o '"gpu_ms": *[0-9.]*' "$OUT/p.json")"
  else
    echo "$lab FAILED"
  fi
}
for round in 1 2; do
  for bin in "$A" "$B"; do
    n="$round $(basename "$bin")"
    run "$bin" "$n restir" $S --spp 2
    run "$bin" "$n point_mis" "$P" --set integrator.type=point_mis --spp 16
    run "$bin" "$n visopt" $S --set integrator.type=visopt --spp 16
    run "$bin" "$n ament" "$P" --set integrator.type=ament --set integrator.step=0.02 --spp 1
  done
done
