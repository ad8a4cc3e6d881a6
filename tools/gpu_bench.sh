#!/usr/bin/env bash
# Every GPU timing of docs/results/gpu.md in one call, as markdown tables on stdout:
#
#   peer     the peer scenes of tools/mitsuba_bench.py at 128x128, 1024 spp
#            (GPU and the CPU on every core, with the GPU's submissions);
#   fig1     Peters 2025's Fig. 1 setting (scenes/fig1.toml at 1920x1080,
#            32 spp, `direct`) for every estimator the paper's table names;
#   density  the same setting over sigma_t scales, on the procedural cloud
#            and on the real dragon.vdb (kernel ms and lookups per pixel and
#            sample), with the ratios jackknife / track-length and
#            jackknife / ratio tracking;
#   mitsuba  equal-time MSE against Mitsuba 3 cuda_ad_rgb on the peer scenes
#            at 128x128 and 1024x1024 (tools/mitsuba_bench.py --device gpu;
#            skipped when python3 cannot import mitsuba).
#
#   tools/gpu_bench.sh [path/to/fogbank] [sections, comma separated] > gpu_bench.md
#
# Environment: DRAGON (default data/dragon.vdb), SCALES_DRAGON,
# SCALES_CLOUD (space separated), MITSUBA_OUT (the benchmark's folder),
# FIG1_SIZE ("1920 1080"; smaller only to try the script on lavapipe).
# Each timing follows a discarded warm-up render: an idle GPU runs at a
# fraction of its clock. Needs python3 with numpy and a GPU with timestamp
# queries.
set -euo pipefail
cd "$(dirname "$0")/.."
FB=${1:-target/release/fogbank}
SECTIONS=${2:-peer,fig1,density,mitsuba}
DRAGON=${DRAGON:-data/dragon.vdb}
SCALES_DRAGON=${SCALES_DRAGON:-2 8 16 32 64}
SCALES_CLOUD=${SCALES_CLOUD:-15 60 120 240 480}
THREADS=$(nproc)
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
ESTIMATORS="jackknife track_length ratio_tracking residual_ratio_tracking biased_ray_marching unbiased_ray_marching ray_marching"
read -r FW FH <<< "${FIG1_SIZE:-1920 1080}"
FIG1=(--set camera.width=$FW --set camera.height=$FH)

field() { python3 -c "import json,sys; v=json.load(open('$1')).get('$2'); print('—' if v is None else (f'{v:.1f}' if isinstance(v,float) else v))"; }
ms() { python3 -c "import json; j=json.load(open('$1')); print(f\"{j['render_seconds']*1000:.1f}\")"; }
has() { [[ ",$SECTIONS," == *",$1,"* ]]; }

"$FB" render scenes/fig1.toml --device gpu --spp 4 --stats "$T/w.json" -o "$T/w.exr" >/dev/null 2>&1
echo "Device: $(field "$T/w.json" device); CPU threads: $THREADS; fogbank $("$FB" --version 2>/dev/null || echo '?')"

if has peer; then
  python3 - "$T" <<'PY'
import sys
sys.path.insert(0, "tools")
import mitsuba_common as mc
out = sys.argv[1]
mc.write_vol(f"{out}/grid.vol", mc.make_grid())
for sc in ["env", "point"]:
    with open(f"{out}/{sc}.toml", "w") as f:
        f.write(mc.fogbank_toml(sc, "grid.vol", 128, 128, 1024, seed=1))
PY
  echo
  echo "| scene (128×128, 1024 spp) | GPU ms (kernel) | GPU ms (render loop) | submissions | CPU ms | GPU / CPU (render loop) |"
  echo "|---|---|---|---|---|---|"
  for sc in env point; do
    "$FB" render "$T/$sc.toml" --device gpu --spp 64 -o "$T/w.exr" >/dev/null 2>&1
    "$FB" render "$T/$sc.toml" --device gpu --stats "$T/g.json" -o "$T/g.exr" >/dev/null 2>&1
    "$FB" render "$T/$sc.toml" --threads "$THREADS" --stats "$T/c.json" -o "$T/c.exr" >/dev/null 2>&1
    g=$(ms "$T/g.json"); c=$(ms "$T/c.json")
    echo "| $sc | $(field "$T/g.json" gpu_ms) | $g | $(field "$T/g.json" gpu_submits) | $c | $(python3 -c "print(f'{$c/$g:.1f}×')") |"
  done
fi

# One Fig. 1-setting render per estimator: "| name | ms | lookups |" rows.
fig1_rows() {
  local scene=$1 label=$2; shift 2
  "$FB" render "$scene" --device gpu "${FIG1[@]}" "$@" -o "$T/w.exr" >/dev/null 2>&1
  for e in $ESTIMATORS; do
    "$FB" render "$scene" --device gpu "${FIG1[@]}" "$@" --set integrator.estimator=$e \
      --stats "$T/f_$e.json" -o "$T/f.exr" >/dev/null 2>&1
    echo "| $label | $e | $(field "$T/f_$e.json" gpu_ms) | $(field "$T/f_$e.json" lookups_per_pixel) |"
  done
  python3 - "$T" "$label" <<'PY'
import json, sys
t, label = sys.argv[1], sys.argv[2]
ms = lambda e: json.load(open(f"{t}/f_{e}.json")).get("gpu_ms") or float("nan")
lk = lambda e: json.load(open(f"{t}/f_{e}.json"))["lookups_per_pixel"]
j, tl, rt = ms("jackknife"), ms("track_length"), ms("ratio_tracking")
more = "yes" if lk("ratio_tracking") > lk("jackknife") else "no"
print(f"| {label} | **jackknife / track-length {j / tl:.2f}, / ratio tracking {j / rt:.2f}**"
      f" | ratio tracking needs more lookups: {more} | |")
PY
}

if has fig1; then
  echo
  echo "| Fig. 1 setting (1920×1080, 32 spp) | estimator | GPU ms (kernel) | lookups / pixel / spp |"
  echo "|---|---|---|---|"
  fig1_rows scenes/fig1.toml "cloud, σ_t scale 60"
fi

if has density; then
  sed -e 's/^type = "transmittance"/type = "direct"/' \
      -e "s|vdb = \"[^\"]*\"|vdb = \"$(realpath "$DRAGON")\"|" scenes/dragon.toml > "$T/dragon.toml"
  cat >> "$T/dragon.toml" <<EOF

[[lights]]
type = "envmap"
file = "$PWD/scenes/probes/sky.hdr"
EOF
  python3 - "$T/dragon.toml" <<'PY'
import sys
p = sys.argv[1]
s = open(p).read()
s = s.replace('filter = "stochastic_trilinear"',
              'filter = "stochastic_trilinear"\nalbedo = [0.95, 0.95, 0.95]\nphase = { type = "hg", g = 0.5 }')
open(p, "w").write(s)
PY
  echo
  echo "| density (1920×1080, 32 spp, \`direct\`, sky probe) | estimator | GPU ms (kernel) | lookups / pixel / spp |"
  echo "|---|---|---|---|"
  for s in $SCALES_CLOUD; do
    fig1_rows scenes/fig1.toml "cloud, σ_t scale $s" --set media.0.sigma_t_scale=$s
  done
  for s in $SCALES_DRAGON; do
    fig1_rows "$T/dragon.toml" "dragon.vdb, σ_t scale $s" --set media.0.sigma_t_scale=$s
  done
fi

if has mitsuba; then
  echo
  if python3 -c "import mitsuba" 2>/dev/null; then
    MO=${MITSUBA_OUT:-$T/mitsuba}
    for size in 128 1024; do
      if [ "$size" = 128 ]; then
        spp=16,32,64,128,256,512,1024,2048; ref=32768; budgets=15,25,60
      else
        spp=1,2,4,8,16,32,64; ref=2048; budgets=15,60,250
      fi
      python3 tools/mitsuba_bench.py --fogbank "$FB" --out "$MO/$size" --variant cuda_ad_rgb \
        --device gpu --ref-device gpu --configs ratio,jackknife --threads "$THREADS" \
        --width $size --height $size --ref-spp $ref --spp-list $spp --budgets-ms $budgets \
        > "$MO.$size.log" 2>&1 || { echo "mitsuba_bench failed at $size:"; tail -5 "$MO.$size.log"; continue; }
      sed -n '/^threads = /,$p' "$MO.$size.log"
      echo
    done
  else
    echo "(mitsuba section skipped: python3 cannot import mitsuba)"
  fi
fi
