#!/usr/bin/env bash
# Render a turntable of every model in a folder as a Slurm job array: task I of N renders
# every N-th model (`realist batch --shard I/N`), all tasks writing into one output folder
# on a shared file system, each into its own manifest (manifest.shard-I-of-N.jsonl).
#
#   sbatch examples/batch/slurm.sh /shared/models /shared/renders
#
# Resubmitting the same script after a failure or a time limit skips every model already
# done (a line with status ok in any manifest of the folder, and its images there).
#
# The array is numbered from 1, as --shard is (1-8: eight tasks, eight shards).
#SBATCH --job-name=realist-batch
#SBATCH --array=1-8
#SBATCH --cpus-per-task=4
#SBATCH --mem=4G
#SBATCH --time=02:00:00
#SBATCH --output=realist-batch-%A_%a.log

set -euo pipefail

models=${1:?usage: sbatch slurm.sh MODELS_FOLDER OUTPUT_FOLDER}
out=${2:?usage: sbatch slurm.sh MODELS_FOLDER OUTPUT_FOLDER}

# realist renders with every core it is given; Slurm gives this task --cpus-per-task.
threads=${SLURM_CPUS_PER_TASK:-1}

# Exit status 3 means some models failed (the manifest's lines say which and why); the
# others are done, so the array task is not marked as failed for it. 1 and 2 are mistakes in
# the command or its arguments.
status=0
realist batch "$models" \
    --turntable 36 --size 640x480 \
    --shard "$SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT" \
    --threads "$threads" \
    --timeout 300 \
    --out "$out" || status=$?
if [ "$status" -ne 0 ] && [ "$status" -ne 3 ]; then
    exit "$status"
fi
