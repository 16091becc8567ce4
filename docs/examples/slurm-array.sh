#!/usr/bin/env bash
# A Slurm job array of three tasks, one shard of the conformance suite each. Slurm sets
# SLURM_ARRAY_TASK_ID (0, 1, 2), SLURM_ARRAY_TASK_MIN, _MAX, _STEP and _COUNT; `refraster
# conformance run` reads them (any --array range and step works: the shard is the task's
# position in it). Submit from the source tree with
#   mkdir -p out && sbatch docs/examples/slurm-array.sh
# (Slurm opens the --output log before the script runs, so its directory must exist.)
#SBATCH --job-name=refraster-conformance
#SBATCH --array=0-2
#SBATCH --cpus-per-task=1
#SBATCH --output=out/slurm-%A_%a.log
set -euo pipefail
build/bin/refraster conformance run --against osmesa --output "out/shard-$SLURM_ARRAY_TASK_ID"
