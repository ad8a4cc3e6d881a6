#!/usr/bin/env bash
# Runs the test suite as a new user's plain clone would: in the copy of
# tools/plain_copy.sh (this checkout's committable files, nothing beside
# them: no ../shared, no fetched data), without FOGBANK_REQUIRE_DATA or
# FOGBANK_DATA_DIR. A test that reads a file outside the repository without
# the data helper (fogbank_math::testdata) fails here; one that goes through
# it passes and skips, and the skips are listed at the end with their
# reasons. `.ci/run` runs it after the main suite.
#
#   tools/test_plain_clone.sh [CARGO TEST ARGS…]
#
# With FOGBANK_DATA_LOG naming the file a run with the data wrote (each test
# that asked fogbank_math::sample_data for an external file appends its name;
# `.ci/run`'s first pass sets it), only those tests run: the rest read no
# external data and would only repeat the first pass's minutes.
#
# Left out, because they read no data of their own and only repeat the main
# run's minutes: the GPU tests (WGPU_BACKEND names a backend Linux lacks, so
# they skip as on a machine without an adapter), the viewer under Xvfb, the
# single-node Slurm and the Kubernetes schema checks.
set -euo pipefail
copy=$("$(dirname "$0")/plain_copy.sh")
cd "$copy"
if [ -e ../shared ] || [ -e data/fetched ] || [ -e data/mni ]; then
    echo "test_plain_clone.sh: $copy is not a plain clone" >&2
    exit 1
fi
echo "plain copy in $copy (nothing beside it)"
skips=$copy/target/skipped_data.txt
mkdir -p "$copy/target"
: > "$skips"
status=0
only=()
if [ -n "${FOGBANK_DATA_LOG:-}" ]; then
    if [ ! -s "$FOGBANK_DATA_LOG" ]; then
        echo "test_plain_clone.sh: $FOGBANK_DATA_LOG names no test" >&2
        exit 1
    fi
    mapfile -t only < <(sort -u "$FOGBANK_DATA_LOG")
    echo "the ${#only[@]} tests that asked for external data:"
    printf '  %s\n' "${only[@]}"
    only=(--exact "${only[@]}")
    set -- --tests "$@"
fi
env -u FOGBANK_REQUIRE_DATA -u FOGBANK_DATA_LOG -u FOGBANK_DATA_DIR -u FOGBANK_REQUIRE_GPU \
    -u FOGBANK_REQUIRE_DISPLAY -u FOGBANK_REQUIRE_SLURM -u FOGBANK_REQUIRE_KUBE \
    WGPU_BACKEND=metal CARGO_TARGET_DIR="$copy/target" FOGBANK_SKIP_LOG="$skips" \
    cargo test --workspace --no-fail-fast "$@" -- \
    --skip scripted_session --skip slurm_array_job --skip manifests_validate \
    "${only[@]}" || status=$?
echo "tests that skipped for want of external data ($(sort -u "$skips" | wc -l)):"
sort -u "$skips" | sed 's/^/  /'
exit "$status"
