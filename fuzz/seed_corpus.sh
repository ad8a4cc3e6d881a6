#!/bin/sh
# Seeds the (git-ignored) fuzz corpora with the committed OpenVDB fixtures,
# the committed sample data and, when present, the external real-world files
# (tools/fetch_data.sh or ../shared/data).
set -e
cd "$(dirname "$0")"
mkdir -p corpus/vdb corpus/blosc
for f in ../crates/volume/tests/fixtures/vdb/*.vdb ../data/dragon.vdb; do
    [ -f "$f" ] && [ "$(wc -c < "$f")" -le 131072 ] && cp "$f" corpus/vdb/
done
echo "seeded $(ls corpus/vdb | wc -l) vdb inputs"
# NanoVDB: the committed (ZIP and BLOSC) fixtures, and one grid stored
# uncompressed and as a raw grid buffer, so that mutations reach the tree
# and not only the compressed streams.
mkdir -p corpus/nanovdb
for f in ../crates/volume/tests/fixtures/nanovdb/*.nvdb; do
    [ -f "$f" ] && cp "$f" corpus/nanovdb/
done
python3 - <<'PY'
import struct, zlib
zip_file = open("../crates/volume/tests/fixtures/nanovdb/fog_zip.nvdb", "rb").read()
name_size = struct.unpack_from("<I", zip_file, 16 + 136)[0]
start = 16 + 176 + name_size
grid = zlib.decompress(zip_file[start + 8:])
head = bytearray(zip_file[:start])
struct.pack_into("<H", head, 14, 0)
struct.pack_into("<Q", head, 16 + 8, len(grid))
struct.pack_into("<H", head, 16 + 168, 0)
open("corpus/nanovdb/fog_none.nvdb", "wb").write(bytes(head) + grid)
open("corpus/nanovdb/fog_raw_grid.nvdb", "wb").write(grid)
PY
echo "seeded $(ls corpus/nanovdb | wc -l) nanovdb inputs"
mkdir -p corpus/vol
for f in ../data/fetched/*.vol ../../shared/data/*.vol ../scenes/mitsuba/textures/*.vol \
    ../scenes/pbrt/mitsuba/data/*.vol ../crates/volume/tests/fixtures/sci/*.vol; do
    [ -f "$f" ] && [ "$(wc -c < "$f")" -le 65536 ] && cp "$f" "corpus/vol/$(basename "$f")"
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
# Meshes: the repository's meshes that fit the targets' 64 KiB, and small
# OBJ and PLY (ASCII and binary) files written here.
mkdir -p corpus/obj corpus/ply
for f in ../scenes/*/meshes/*.obj ../scenes/*/meshes/*.ply ../scenes/*/*.obj; do
    [ -f "$f" ] && [ "$(wc -c < "$f")" -le 65536 ] && cp "$f" "corpus/${f##*.}/$(basename "$f")"
done
printf 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1 4/4/1\n' > corpus/obj/quad.obj
printf 'o a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\ng b\nv 0 0 1\nf 1 2 4\n' > corpus/obj/groups.obj
printf 'ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\nproperty float u\nproperty float v\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0 0 0 1 0 0\n1 0 0 0 0 1 1 0\n1 1 0 0 0 1 1 1\n0 1 0 0 0 1 0 1\n4 0 1 2 3\n' > corpus/ply/quad_ascii.ply
python3 - <<'PY'
import struct
h = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar uint vertex_indices\nend_header\n"
body = b"".join(struct.pack("<3f", *p) for p in [(0, 0, 0), (1, 0, 0), (0, 1, 0)]) + struct.pack("<B3I", 3, 0, 1, 2)
open("corpus/ply/tri_le.ply", "wb").write(h + body)
hb = h.replace(b"binary_little_endian", b"binary_big_endian")
body = b"".join(struct.pack(">3f", *p) for p in [(0, 0, 0), (1, 0, 0), (0, 1, 0)]) + struct.pack(">B3I", 3, 0, 1, 2)
open("corpus/ply/tri_be.ply", "wb").write(hb + body)
PY
echo "seeded $(ls corpus/obj | wc -l) obj and $(ls corpus/ply | wc -l) ply inputs"
mkdir -p corpus/xml
for f in ../scenes/mitsuba/*.xml; do
    [ -f "$f" ] && cp "$f" corpus/xml/
done
echo "seeded $(ls corpus/xml | wc -l) xml inputs"
# Partial results: the committed one without its checksum (the target seals
# every input with a valid one).
mkdir -p corpus/fbpart
for f in ../crates/partial/tests/fixtures/*.fbpart; do
    head -c -8 "$f" > "corpus/fbpart/$(basename "$f")"
done
echo "seeded $(ls corpus/fbpart | wc -l) fbpart inputs"
# pbrt-v4 scenes: the reader's fixtures and the pbrt-v4-scenes texts.
mkdir -p corpus/pbrt
for f in ../crates/scene/tests/pbrt/*.pbrt ../crates/scene/tests/pbrt/*/*.pbrt ../crates/scene/tests/pbrt/v4-scenes/*/*.pbrt; do
    [ -f "$f" ] && cp "$f" "corpus/pbrt/$(basename "$(dirname "$f")")_$(basename "$f")"
done
echo "seeded $(ls corpus/pbrt | wc -l) pbrt inputs"
# The minimised corpora of the runs in docs/results/fuzzing.md, so that a
# new run resumes where the last one stopped.
for d in corpora/*/; do
    [ -d "$d" ] || continue
    t="$(basename "$d")"
    mkdir -p "corpus/$t"
    cp "$d"* "corpus/$t/" 2>/dev/null || true
    echo "resumed $(ls "$d" | wc -l) committed $t inputs"
done
# Targets whose inputs up to 16 KiB lose coverage keep their whole
# minimised corpus as one compressed archive.
for a in corpora/*.tar.xz; do
    [ -f "$a" ] || continue
    tar -C corpus -xJf "$a"
    echo "resumed $(tar -tJf "$a" | grep -vc '/$') committed $(basename "$a" .tar.xz) inputs"
done
