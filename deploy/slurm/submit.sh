#!/usr/bin/env bash
# Render SCENE on a Slurm cluster in N exact shards, then merge them:
#
#   deploy/slurm/submit.sh SCENE N OUT_DIR [prism render args ...]
#   e.g. deploy/slurm/submit.sh scenes/cornell_box.ron 16 /shared/run1 --spp 4096
#
# Submits a job array of N tasks (render_shard.sbatch, one shard each) and a merge job (merge.sbatch) that runs
# only if every array task succeeded (--dependency=afterok). OUT_DIR must be on a file system every node sees.
# Prints the two job ids. Set PRISM to the binary's path on the nodes, OUTPUT for the merged file name
# (default render.exr), SBATCH_ARGS for extra sbatch options (partition, account, time limit ...).
set -euo pipefail
if [ $# -lt 3 ]; then
    echo "usage: $0 SCENE N OUT_DIR [prism render args ...]" >&2
    exit 2
fi
SCENE="$(realpath "$1")"; SHARDS="$2"; OUT_DIR="$(realpath -m "$3")"; shift 3
case "$SHARDS" in ''|*[!0-9]*|0) echo "N must be a positive integer, got '$SHARDS'" >&2; exit 2 ;; esac
mkdir -p "$OUT_DIR"
HERE="$(cd "$(dirname "$0")" && pwd)"
export PRISM="${PRISM:-$(command -v prism || echo prism)}" SCENE OUT_DIR SHARDS OUTPUT="${OUTPUT:-render.exr}"
export RENDER_ARGS="$*"
# shellcheck disable=SC2086
array=$(sbatch --parsable --chdir="$OUT_DIR" --array="0-$((SHARDS - 1))" --export=ALL ${SBATCH_ARGS:-} \
    "$HERE/render_shard.sbatch")
array="${array%%;*}"
# shellcheck disable=SC2086
merge=$(sbatch --parsable --chdir="$OUT_DIR" --dependency="afterok:$array" --kill-on-invalid-dep=yes --export=ALL \
    ${SBATCH_ARGS:-} "$HERE/merge.sbatch")
echo "array $array merge ${merge%%;*}"
