#!/usr/bin/env bash
# GPU timings of issue 21 in one call, as a markdown table on stdout:
# the peer scenes of tools/mitsuba_bench.py at 128x128, 1024 spp (GPU and
# the CPU on every core, with the GPU's submissions), and seed 000's Fig. 1
# setting (scenes/fig1.toml at 1920x1080, 32 spp) for every estimator the
# paper's table names. Each timing follows a discarded warm-up render: an
# idle GPU runs at a fraction of its clock.
#
#   tools/gpu_bench.sh [path/to/fogbank] > gpu_bench.md
#
# Needs python3 with numpy (the peer scenes' grid) and a GPU with
# timestamp queries.
set -euo pipefail
cd "$(dirname "$0")/.."
FB=${1:-target/release/fogbank}
THREADS=$(nproc)
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
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
field() { python3 -c "import json,sys; v=json.load(open('$1')).get('$2'); print('—' if v is None else (f'{v:.1f}' if isinstance(v,float) else v))"; }
ms() { python3 -c "import json; j=json.load(open('$1')); print(f\"{j['render_seconds']*1000:.1f}\")"; }
"$FB" render "$T/env.toml" --device gpu --spp 64 --stats "$T/w.json" -o "$T/w.exr" >/dev/null 2>&1
echo "Device: $(field "$T/w.json" device); CPU threads: $THREADS"
echo
echo "| scene (128×128, 1024 spp) | GPU ms (kernel) | submissions | CPU ms | GPU / CPU |"
echo "|---|---|---|---|---|"
for sc in env point; do
  "$FB" render "$T/$sc.toml" --device gpu --spp 64 -o "$T/w.exr" >/dev/null 2>&1
  "$FB" render "$T/$sc.toml" --device gpu --stats "$T/g.json" -o "$T/g.exr" >/dev/null 2>&1
  "$FB" render "$T/$sc.toml" --threads "$THREADS" --stats "$T/c.json" -o "$T/c.exr" >/dev/null 2>&1
  g=$(field "$T/g.json" gpu_ms); c=$(ms "$T/c.json")
  echo "| $sc | $g | $(field "$T/g.json" gpu_submits) | $c | $(python3 -c "print(f'{$c/$g:.1f}×')") |"
done
echo
echo "| Fig. 1 setting (1920×1080, 32 spp) | GPU ms (kernel) | lookups / pixel / spp |"
echo "|---|---|---|"
fig1=(--set camera.width=1920 --set camera.height=1080)
"$FB" render scenes/fig1.toml --device gpu "${fig1[@]}" -o "$T/w.exr" >/dev/null 2>&1
for e in jackknife track_length ratio_tracking residual_ratio_tracking biased_ray_marching unbiased_ray_marching ray_marching; do
  "$FB" render scenes/fig1.toml --device gpu "${fig1[@]}" --set integrator.estimator=$e \
    --stats "$T/f.json" -o "$T/f.exr" >/dev/null 2>&1
  echo "| $e | $(field "$T/f.json" gpu_ms) | $(field "$T/f.json" lookups_per_pixel) |"
done
