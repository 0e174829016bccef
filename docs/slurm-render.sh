#!/bin/bash
# Renders one image as a grid of tiles on a Slurm cluster, one array task per tile, then joins
# the tiles into one tiled OpenEXR. spectex needs no scheduler of its own: each task reads its
# tile index from SLURM_ARRAY_TASK_ID (row-major from the top-left, 0 to COLS·ROWS − 1).
#
# Submit (the array range must be 0 to COLS·ROWS − 1; 8x8 tiles here; Slurm opens the logs
# below before the script runs, so their directory must exist):
#   mkdir -p tiles && sbatch --array=0-63 docs/slurm-render.sh model.json
# then, once every task has finished (or chain it with --dependency=afterok:<array job id>):
#   spectex assemble tiles/tile-*.exr -o whole.exr
#
# Each task holds one band of its tile's rows in memory, not the tile: a few tens of MB.
#SBATCH --job-name=spectex-render
#SBATCH --cpus-per-task=4
#SBATCH --mem=1G
#SBATCH --time=01:00:00
#SBATCH --output=tiles/tile-%a.log

set -euo pipefail

MODEL="${1:?give the model file: sbatch --array=0-63 docs/slurm-render.sh model.json}"
SIZE="${SIZE:-65536x65536}"   # the whole image
GRID="${GRID:-8x8}"           # COLSxROWS; the --array range is 0 to COLS·ROWS − 1
OUT_DIR="${OUT_DIR:-tiles}"

mkdir -p "$OUT_DIR"
# Rayon uses the CPUs Slurm gave the task, not the node's.
export RAYON_NUM_THREADS="${SLURM_CPUS_PER_TASK:-1}"
# Without --tile-index, spectex reads SLURM_ARRAY_TASK_ID. Re-running a task rewrites its tile
# whole (a temporary file renamed into place), so a failed task can simply be resubmitted.
spectex render "$MODEL" --size "$SIZE" --tiles "$GRID" \
    -o "$OUT_DIR/tile-${SLURM_ARRAY_TASK_ID}.exr"
