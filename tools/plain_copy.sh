#!/usr/bin/env bash
# Makes a copy of this checkout as a plain clone would hold it and prints
# its path: the files git tracks plus the untracked ones it does not ignore
# (what `git add -A` would commit), in target/plain/fogbank with nothing
# beside it: no ../shared, no fetched data (data/fetched/, data/mni/). Each
# call refreshes the files; the copy's own target/ folder is kept, so tests
# there build incrementally. Build there with CARGO_TARGET_DIR unset or set
# to COPY/target: a target folder shared with this checkout would mix the
# two checkouts' paths (cargo names their artifacts alike).
set -euo pipefail
cd "$(dirname "$0")/.."
copy=$PWD/target/plain/fogbank
mkdir -p "$copy"
find "$copy" -mindepth 1 -maxdepth 1 ! -name target -exec rm -rf {} +
git ls-files -z --cached --others --exclude-standard |
    while IFS= read -r -d '' f; do [ -e "$f" ] && printf '%s\0' "$f"; done |
    tar --null -T - -cf - | tar -xf - -C "$copy"
echo "$copy"
