#!/usr/bin/env bash
# Runs the test suite as a new user's plain clone would: from a `git clone`
# of HEAD in an empty temporary folder, with no ../shared beside it, no
# fetched data (data/fetched/, data/mni/) and nothing uncommitted, and
# without FOGBANK_REQUIRE_DATA. A test that reads a file outside the
# repository without the data helper (fogbank_math::testdata) fails here;
# one that goes through it prints SKIPPED and passes. `.ci/run` runs it
# after the main suite.
#
#   tools/test_plain_clone.sh [CARGO TEST ARGS…]
#
# Left out, because they read no data of their own and only repeat the main
# run's minutes: the GPU tests (WGPU_BACKEND names a backend Linux lacks, so
# they skip as on a machine without an adapter), the viewer under Xvfb, the
# single-node Slurm and the Kubernetes schema checks. Crates rebuild for the
# clone's paths (about as long as a change to fogbank-math); dependencies
# come from this checkout's target folder.
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$PWD
target=${CARGO_TARGET_DIR:-$repo/target}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
git clone -q --no-local "$repo" "$work/fogbank"
cd "$work/fogbank"
if [ -e ../shared ] || [ -e data/fetched ] || [ -e data/mni ]; then
    echo "test_plain_clone.sh: $work is not empty around the clone" >&2
    exit 1
fi
echo "plain clone of $(git rev-parse --short HEAD) in $work/fogbank (nothing beside it)"
env -u FOGBANK_REQUIRE_DATA -u FOGBANK_REQUIRE_GPU -u FOGBANK_REQUIRE_DISPLAY \
    -u FOGBANK_REQUIRE_SLURM -u FOGBANK_REQUIRE_KUBE \
    WGPU_BACKEND=metal CARGO_TARGET_DIR="$target" \
    cargo test --workspace --no-fail-fast "$@" -- \
    --skip scripted_session --skip slurm_array_job --skip manifests_validate
