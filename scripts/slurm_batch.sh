#!/usr/bin/env bash
# One shard of a shadelab batch as a Slurm job-array task (docs/batch.md, "Cluster runs"):
#   sbatch --array=1-16 --cpus-per-task=4 scripts/slurm_batch.sh jobs.txt out
# then, when every task has finished:
#   shadelab report merge out/batch_report_shard*of16.json -o out/batch_report.json
#SBATCH --job-name=shadelab
#SBATCH --output=shadelab_%A_%a.log
set -euo pipefail
manifest="${1:?usage: slurm_batch.sh MANIFEST OUT_DIR}"
out="${2:?usage: slurm_batch.sh MANIFEST OUT_DIR}"
i="${SLURM_ARRAY_TASK_ID:?not a Slurm array task (SLURM_ARRAY_TASK_ID is unset)}"
n="${SLURM_ARRAY_TASK_COUNT:?not a Slurm array task (SLURM_ARRAY_TASK_COUNT is unset)}"
# PoCL starts one thread per core it sees; on a shared node use the cores Slurm gave this task.
export POCL_MAX_PTHREAD_COUNT="${SLURM_CPUS_PER_TASK:-1}"
exec "${SHADELAB:-shadelab}" batch --manifest "$manifest" --out "$out" --shard "$i/$n" --progress lines
