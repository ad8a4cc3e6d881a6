#!/bin/sh
# Copies the MNI152 (ICBM 2009a, 1 mm) brain templates that ship inside the
# nilearn package — T1 and grey/white-matter probability maps, freely
# available — into data/mni/ (git-ignored), for scenes/mri_brain.toml and
# the seed 003 experiments. Needs python3 with venv; nothing else.
set -e
cd "$(dirname "$0")/.."
mkdir -p data/mni
venv=$(mktemp -d)/venv
python3 -m venv "$venv"
"$venv/bin/pip" install -q nilearn
src=$("$venv/bin/python" -c 'import nilearn.datasets, os; print(os.path.join(os.path.dirname(nilearn.datasets.__file__), "data"))')
for q in t1 gm wm; do
    cp "$src/mni_icbm152_${q}_tal_nlin_sym_09a_converted.nii.gz" "data/mni/mni_${q}.nii.gz"
done
rm -rf "$(dirname "$venv")"
ls -l data/mni
