#!/bin/sh
# Fetches the real volume files that are too large for the repository (see
# data/README.md) into git-ignored folders of data/:
#
#   tools/fetch_data.sh [mni] [vdb] [vol]     (no argument: all three)
#
#   mni  the MNI152 (ICBM 2009a, 1 mm) T1 and grey/white-matter templates,
#        from the nilearn wheel on PyPI (only the wheel is downloaded, no
#        dependencies), into data/mni/: scenes/mri_brain.toml and Lerzer and Dachsbacher 2025's
#        head studies.
#   vdb  openvdb.org's sample models cube.vdb (Hansen 2025's Cube stand-ins) and
#        sphere.vdb (the original, format 222; the reader's tests), into
#        data/fetched/.
#   vol  Mitsuba 3's test grids sigmat.vol and albedo.vol (the .vol reader's
#        tests), into data/fetched/.
#
# A file already in $FOGBANK_DATA_DIR or ../shared/data (beside the
# repository) is copied from there instead of downloaded. Needs python3 with
# pip; nothing else.
set -eu
cd "$(dirname "$0")/.."
what=${*:-mni vdb vol}
shared=${FOGBANK_DATA_DIR:-../shared/data}

# fetch URL FILE_IN_ZIP DEST: DEST from $shared, else from URL (a zip
# holding FILE_IN_ZIP, or the file itself when FILE_IN_ZIP is empty).
fetch() {
    name=$(basename "$3")
    mkdir -p data/fetched
    if [ -f "$shared/$name" ]; then
        cp -f "$shared/$name" "$3"
        chmod 644 "$3"
        return
    fi
    python3 - "$1" "$2" "$3" <<'EOF'
import io, sys, urllib.request, zipfile
url, member, dest = sys.argv[1:]
data = urllib.request.urlopen(url, timeout=120).read()
if member:
    data = zipfile.ZipFile(io.BytesIO(data)).read(member)
open(dest, "wb").write(data)
EOF
}

for w in $what; do
    case $w in
    mni)
        mkdir -p data/mni
        tmp=$(mktemp -d)
        python3 -m pip download -q --no-deps --only-binary=:all: nilearn==0.14.1 -d "$tmp"
        python3 - "$tmp"/nilearn-*.whl <<'EOF'
import sys, zipfile
z = zipfile.ZipFile(sys.argv[1])
for q in ("t1", "gm", "wm"):
    src = "nilearn/datasets/data/mni_icbm152_%s_tal_nlin_sym_09a_converted.nii.gz" % q
    open("data/mni/mni_%s.nii.gz" % q, "wb").write(z.read(src))
EOF
        rm -rf "$tmp"
        ls -l data/mni
        ;;
    vdb)
        models=https://artifacts.aswf.io/io/aswf/openvdb/models
        fetch "$models/cube.vdb/1.0.0/cube.vdb-1.0.0.zip" cube.vdb data/fetched/cube.vdb
        fetch "$models/sphere.vdb/1.0.0/sphere.vdb-1.0.0.zip" sphere.vdb data/fetched/sphere.vdb
        ;;
    vol)
        textures=https://raw.githubusercontent.com/mitsuba-renderer/mitsuba-data/master/tests/scenes/participating_media/textures
        fetch "$textures/sigmat.vol" "" data/fetched/sigmat.vol
        fetch "$textures/albedo.vol" "" data/fetched/albedo.vol
        ;;
    *)
        echo "fetch_data.sh: unknown set '$w' (expected mni, vdb or vol)" >&2
        exit 2
        ;;
    esac
done
if [ -d data/fetched ]; then ls -l data/fetched; fi
