#!/bin/sh
# Seeds the (git-ignored) fuzz corpora with the committed OpenVDB fixtures
# and, when present, the shared real-world files.
set -e
cd "$(dirname "$0")"
mkdir -p corpus/vdb corpus/blosc
for f in ../crates/volume/tests/fixtures/vdb/*.vdb ../../shared/data/dragon.vdb; do
    [ -f "$f" ] && [ "$(wc -c < "$f")" -le 131072 ] && cp "$f" corpus/vdb/
done
echo "seeded $(ls corpus/vdb | wc -l) vdb inputs"
mkdir -p corpus/vol
for f in ../../shared/data/*.vol; do
    [ -f "$f" ] && cp "$f" corpus/vol/
done
echo "seeded $(ls corpus/vol | wc -l) vol inputs"
mkdir -p corpus/nifti corpus/nrrd
for f in ../crates/volume/tests/fixtures/sci/*.nii ../crates/volume/tests/fixtures/sci/*.nii.gz; do
    [ -f "$f" ] && cp "$f" corpus/nifti/
done
for f in ../crates/volume/tests/fixtures/sci/*.nrrd ../crates/volume/tests/fixtures/sci/*.nhdr; do
    [ -f "$f" ] && cp "$f" corpus/nrrd/
done
echo "seeded $(ls corpus/nifti | wc -l) nifti and $(ls corpus/nrrd | wc -l) nrrd inputs"
# Blosc frames: two little-endian bytes of expected size, then the frame.
python3 - <<'PY'
import base64, json, os
v = json.load(open("../crates/volume/tests/fixtures/vdb/blosc_frames.json"))
payloads = [base64.b64decode(p) for p in v["payloads"]]
for i, fr in enumerate(v["frames"]):
    n = len(payloads[fr["payload"]])
    with open(os.path.join("corpus/blosc", "frame%02d" % i), "wb") as f:
        f.write(n.to_bytes(2, "little") + base64.b64decode(fr["frame"]))
print("seeded %d blosc frames" % len(v["frames"]))
PY
