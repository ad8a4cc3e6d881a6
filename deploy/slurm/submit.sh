#!/usr/bin/env bash
# Submits a sharded fogbank render to Slurm: an array job of N shards and a
# merge job that runs when all of them have succeeded.
#
#   deploy/slurm/submit.sh N SCENE.toml OUT.exr [fogbank render options]
#
# Parts go to OUT_parts/ (the folder must be on storage every node sees).
# Environment: FOGBANK (the binary; default fogbank on PATH), SBATCH_ARGS
# (extra sbatch options for the shards, e.g. "--cpus-per-task=16 --time=2:00:00").
# Prints the two job ids.
set -euo pipefail
n=${1:?usage: submit.sh N SCENE OUT.exr [render options]}
scene=${2:?usage: submit.sh N SCENE OUT.exr [render options]}
out=${3:?usage: submit.sh N SCENE OUT.exr [render options]}
shift 3
here=$(cd "$(dirname "$0")" && pwd)
parts="${out%.*}_parts"
mkdir -p "$parts"
# shellcheck disable=SC2086 # SBATCH_ARGS is a list of options
array=$(sbatch --parsable --array=0-$((n - 1)) ${SBATCH_ARGS:-} "$here/render_shard.sbatch" "$scene" "$parts" "$@")
merge=$(sbatch --parsable --dependency=afterok:"$array" --kill-on-invalid-dep=yes "$here/merge.sbatch" "$parts" "$out")
echo "$array $merge"
