#!/bin/bash
# properties = {properties}
# Snakemake job script for SLURM. A SIGTERM from SLURM (`scancel --signal=TERM --batch`, or
# `--signal=B:TERM@<s>` before the time limit) reaches the simulator, which writes its checkpoint
# and exits non-zero; Snakemake and the shells between ignore it, so the job fails cleanly, is
# resubmitted (restart-times) and resumes. The job runs in its own process group (set -m).
set -m
( trap '' TERM; {exec_job} ) &
child=$!
trap 'trap "" TERM; kill -TERM -- -$child' TERM
while kill -0 "$child" 2>/dev/null; do wait "$child"; done
wait "$child"
