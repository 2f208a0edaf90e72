#!/usr/bin/env bash
# GaussLOD on a manifest as a Slurm array job: task k of N runs `gausslod batch` on the manifest's
# data lines i with i % N == k (see tools/batch.cpp; outputs and records in OUTDIR, idempotent:
# a requeued or resubmitted task skips what is done).
#   sbatch --array=0-15 tools/gausslod_slurm.sh MANIFEST OUTDIR [gausslod options...]
# Use a contiguous range (no :step). GAUSSLOD = the gausslod binary (default: gausslod on PATH).
#SBATCH --job-name=gausslod
#SBATCH --cpus-per-task=2
#SBATCH --output=gausslod-%A_%a.jsonl
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: sbatch --array=0-N $0 MANIFEST OUTDIR [options]" >&2; exit 2; }
: "${SLURM_ARRAY_TASK_ID:?run it as a Slurm array job: sbatch --array=0-N $0 MANIFEST OUTDIR}"
first=${SLURM_ARRAY_TASK_MIN:-0}
count=${SLURM_ARRAY_TASK_COUNT:-$((${SLURM_ARRAY_TASK_MAX:-$SLURM_ARRAY_TASK_ID} - first + 1))}
manifest=$1 outdir=$2; shift 2
exec "${GAUSSLOD:-gausslod}" batch --threads "${SLURM_CPUS_PER_TASK:-0}" "$@" "$manifest" "$outdir" \
  --part "$((SLURM_ARRAY_TASK_ID - first))/$count"
