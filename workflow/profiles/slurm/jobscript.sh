#!/bin/bash
# properties = {properties}
# Snakemake job script for SLURM. A SIGTERM from SLURM (`scancel --signal=TERM --batch`, or
# `--signal=B:TERM@<s>` before the time limit) is passed to the job's process group (set -m): the
# simulator (started by `exec`, no shell in between) writes its checkpoint and exits non-zero,
# Snakemake waits for it (its graceful stop) and fails, and the job is resubmitted
# (restart-times) and resumes. This shell and its subshell ignore the signal.
set -m
( trap '' TERM; {exec_job} ) &
child=$!
trap 'trap "" TERM; kill -TERM -- -$child' TERM
while kill -0 "$child" 2>/dev/null; do wait "$child"; done
wait "$child"
