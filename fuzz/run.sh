#!/bin/sh
# Runs one fuzz target with the limits that target needs, or keeps what a
# run found:
#   ./run.sh TARGET [SECONDS]   fuzz for SECONDS (default 3600) and print
#                               libFuzzer's final statistics (the figures
#                               of docs/results/fuzzing.md)
#   ./run.sh --keep TARGET      minimise corpus/TARGET (cargo fuzz cmin) and
#                               store it in corpora/ for the next run
#
# The limits are those of the runs recorded there. A memory limit bounds
# what one input may make a reader allocate (the readers validate sizes
# against the input before allocating); nanovdb's is larger because a
# compressed grid may legitimately inflate up to 1100 times its stored size
# (README.md). pbrt silences the reader's notices on stderr.
set -e
cd "$(dirname "$0")"
keep=0
if [ "$1" = "--keep" ]; then keep=1; shift; fi
target="${1:?usage: ./run.sh TARGET [SECONDS] | ./run.sh --keep TARGET}"
seconds="${2:-3600}"
case "$target" in
    vdb) limits="-malloc_limit_mb=32 -max_len=131072" ;;
    nanovdb) limits="-malloc_limit_mb=1200 -max_len=1048576" ;;
    blosc) limits="-malloc_limit_mb=32" ;;
    vol | nifti | nrrd | ply | obj) limits="-malloc_limit_mb=64 -max_len=65536" ;;
    fbpart) limits="-malloc_limit_mb=128 -max_len=65536" ;;
    xml) limits="-malloc_limit_mb=256 -max_len=16384" ;;
    pbrt) limits="-close_fd_mask=2" ;;
    *) echo "unknown target '$target' (targets: $(ls fuzz_targets | sed 's/\.rs$//' | tr '\n' ' '))" >&2; exit 2 ;;
esac
mkdir -p "corpus/$target"
export RUSTC_BOOTSTRAP=1
if [ "$keep" = 0 ]; then
    # shellcheck disable=SC2086 # the limits are separate arguments
    exec cargo fuzz run "$target" -- -max_total_time="$seconds" $limits -print_final_stats=1
fi
# shellcheck disable=SC2086
cargo fuzz cmin "$target" -- $limits
# Inputs up to 16 KiB as files; a target whose corpus is kept as an archive
# (where the inputs up to 16 KiB lose coverage; `touch corpora/TARGET.tar.xz`
# makes one such) keeps the whole corpus that way.
if [ -f "corpora/$target.tar.xz" ]; then
    tar -C corpus --sort=name --mtime=@0 --owner=0 --group=0 --numeric-owner -cf - "$target" |
        xz -6 > "corpora/$target.tar.xz"
else
    rm -rf "corpora/$target" && mkdir -p "corpora/$target"
    find "corpus/$target" -type f -size -16385c -exec cp {} "corpora/$target/" \;
fi
echo "kept $(ls "corpus/$target" | wc -l) minimised $target inputs in corpora/"
