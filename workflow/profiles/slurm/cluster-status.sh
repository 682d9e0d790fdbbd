#!/usr/bin/env bash
# Snakemake `cluster-status` for SLURM: prints success, running or failed for the job id that
# `sbatch --parsable` returned (Snakemake passes it as the only argument).
# sacct where the site keeps accounting; otherwise (no slurmdbd, as on the one-node test cluster)
# scontrol, which knows a job until MinJobAge (300 s by default) after it ended.
set -u
jobid=${1%%;*}  # --parsable prints "id" or "id;cluster"
state=""
if out=$(sacct -j "$jobid" -X -n -P -o State 2>/dev/null) && [ -n "$out" ]; then
  state=${out%%$'\n'*}
  state=${state%% *}  # "CANCELLED by 0" -> CANCELLED
elif out=$(scontrol show job -o "$jobid" 2>&1); then
  state=$(grep -o 'JobState=[A-Z_]*' <<<"$out" | head -n 1)
  state=${state#JobState=}
elif grep -qi 'invalid job id' <<<"$out"; then
  state=UNKNOWN_JOB  # purged long after it ended: reported failed (Snakemake polls far more often)
fi
case "$state" in
  COMPLETED) echo success ;;
  "" | PENDING | CONFIGURING | RUNNING | COMPLETING | SUSPENDED | REQUEUED | REQUEUE_FED | \
    REQUEUE_HOLD | RESIZING | SIGNALING | STAGE_OUT | STOPPED | RESV_DEL_HOLD | SPECIAL_EXIT)
    echo running ;;  # "": the controller did not answer; ask again at the next poll
  *) echo failed ;;  # FAILED, CANCELLED, TIMEOUT, PREEMPTED, NODE_FAIL, OUT_OF_MEMORY, ...
esac
