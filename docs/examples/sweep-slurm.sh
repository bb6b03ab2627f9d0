#!/bin/bash
# A parameter study as a Slurm job array: one array task per case, then one job that gathers the
# summary once every task has ended (whatever their exit status: a failed case is a row too).
#
#   mkdir -p logs
#   N=$(pendulum-fem sweep --file docs/examples/study.toml --list)
#   ARRAY=$(sbatch --parsable --array=0-$((N - 1))%50 docs/examples/sweep-slurm.sh)
#   sbatch --dependency=afterany:$ARRAY --wrap "pendulum-fem sweep --gather study"
#
# `%50` runs at most 50 cases at once. Every task writes only its own folder study/case-NNNN/
# (and study/cases.csv, the same text from every task), so tasks never collide; the sweep folder
# must be on a file system that all nodes see. A task that is requeued or run again starts its
# case afresh; add --resume to keep a case that finished. One case is one small run: one core.
#
#SBATCH --job-name=pendulum-sweep
#SBATCH --cpus-per-task=1
#SBATCH --mem=1G
#SBATCH --time=00:30:00
#SBATCH --output=logs/%x-%A_%a.out

set -euo pipefail
# The case comes from SLURM_ARRAY_TASK_ID (the same as --case-index "$SLURM_ARRAY_TASK_ID").
exec pendulum-fem sweep --file docs/examples/study.toml --out study --quiet
