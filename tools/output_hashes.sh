#!/usr/bin/env bash
# Hashes of what users see, to prove a refactor changed nothing:
# the CPU and GPU (lavapipe or any adapter) images of every scene in
# scenes/ and of each integrator on the built-in scene, at a low fixed spp,
# and `fogbank stats` outputs (EXR and summary.json without timings) for
# every estimator.
#
#   tools/output_hashes.sh [FOGBANK_BINARY] > hashes.txt
#   tools/output_hashes.sh --check tools/output_hashes.txt [FOGBANK_BINARY]
#
# Each line is `sha256  what`. With --check, the fresh hashes are compared
# with the file and every difference is listed (exit 1 if any).
# Set FOGBANK_HASH_GPU=0 to skip the GPU half.
set -euo pipefail
cd "$(dirname "$0")/.."

check=""
if [ "${1:-}" = "--check" ]; then
  check="$2"
  shift 2
fi
bin="${1:-}"
if [ -z "$bin" ]; then
  cargo build --release -q -p fogbank-cli
  bin="target/release/fogbank"
fi
gpu="${FOGBANK_HASH_GPU:-1}"

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
out="$work/hashes.txt"
: > "$out"

# Pixel data only: the EXR's bytes are a function of the pixels (no time
# stamps are written), so the file hash is the image hash.
hash_file() { sha256sum "$1" | cut -d' ' -f1; }

render() { # name device args...
  local name="$1" device="$2"
  shift 2
  local f="$work/$name.$device.exr"
  if "$bin" render "$@" --device "$device" --threads 2 --quiet -o "$f" 2>"$work/err"; then
    echo "$(hash_file "$f")  render $name $device" >> "$out"
  else
    echo "error  render $name $device: $(tail -1 "$work/err")" >> "$out"
  fi
}

small=(--set camera.width=48 --set camera.height=32 --spp 4 --seed 3)
devices=(cpu)
[ "$gpu" = 1 ] && devices+=(gpu)

for d in "${devices[@]}"; do
  for s in scenes/*.toml; do
    render "$(basename "$s" .toml)" "$d" "$s" "${small[@]}"
  done
  render builtin "$d" "${small[@]}"
  render builtin-direct "$d" "${small[@]}" --set integrator.type=direct --set integrator.estimator=jackknife
  render builtin-volpath "$d" "${small[@]}" --set integrator.type=volpath --set integrator.max_depth=6
  render builtin-baseline "$d" "${small[@]}" --set integrator.type=volpath --set integrator.preset=baseline \
    --set integrator.distance_sampler=decomposition_tracking
  render builtin-regular "$d" "${small[@]}" --set integrator.type=volpath --set integrator.distance_sampler=regular_tracking \
    --set integrator.max_depth=3
  for strategy in free_flight equiangular mis_miller mis_naive mis_jackknife mis_jackknife_biased; do
    render "point_mis-$strategy" "$d" "${small[@]}" --set integrator.type=point_mis \
      --set integrator.strategy="$strategy" --set integrator.estimator=jackknife \
      --set 'lights=[{type="point",position=[0.1,0.05,0.0],intensity=[1.0,0.8,0.6]}]'
  done
done

# Every estimator through `fogbank stats` (CPU and GPU), 32 frames of 24×16.
for e in $("$bin" estimators | awk '$1 ~ /^[a-z_]+$/ {print $1}'); do
  for d in "${devices[@]}"; do
    dir="$work/stats-$e-$d"
    if "$bin" stats --estimator "$e" --runs 32 --reference-estimator analytic_trilinear \
      --set camera.width=24 --set camera.height=16 --out "$dir" --device "$d" --threads 2 \
      >/dev/null 2>"$work/err"; then
      echo "$(hash_file "$dir/stats.exr")  stats $e $d stats.exr" >> "$out"
      # summary.json without timings and memory.
      grep -v -E '"(ms_per_frame|seconds|render_seconds|stats_seconds|gpu_ms|peak_memory_bytes|threads|frames_per_second)"' \
        "$dir/summary.json" | sha256sum | cut -d' ' -f1 | sed "s/\$/  stats $e $d summary.json/" >> "$out"
    else
      echo "error  stats $e $d: $(tail -1 "$work/err")" >> "$out"
    fi
  done
done

if [ -z "$check" ]; then
  cat "$out"
else
  if diff <(sort -k2 "$check") <(sort -k2 "$out"); then
    echo "all $(wc -l < "$out") outputs identical"
  else
    echo "outputs differ (< recorded, > now)" >&2
    exit 1
  fi
fi
