#!/usr/bin/env bash
# make test-slurm: the SLURM profile (workflow/profiles/slurm) against a live one-node SLURM.
#
# Starts munged, slurmctld and slurmd on this machine with a generated slurm.conf in a temporary
# folder (own ports and munge socket: nothing system-wide is touched), runs the quick profile's
# GRW05 tail shards, their merges and the tail-exponent table through the profile, preempts one
# shard job on purpose (SIGTERM: it writes its checkpoint, fails, is resubmitted and resumes),
# runs the same targets locally, checks that the results are identical bit for bit, runs a study
# of two points (python -m granboltz.study run --profile) through the profile and locally and
# compares them, and stops everything it started.
#
# Exit codes: 0 passed; 1 failed; 77 this machine cannot host SLURM (reason on stderr).
# Needs root (apt-get and the daemons). KEEP=1 keeps the temporary folder.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
CANNOT=77
PROFILE_CONFIG=$ROOT/config/quick.yaml
TARGETS=(results/tables/grw05_tail_exponents.csv results/tables/grw05_tail_windows.csv)
START=$(date +%s)

say() { echo "test-slurm: $*"; }
cannot() {
  echo "test-slurm: this machine cannot host SLURM: $*" >&2
  exit $CANNOT
}
fail() {
  echo "test-slurm: FAILED: $*" >&2
  exit 1
}

# ------------------------------------------------------------------------------ install
[ "$(id -u)" -eq 0 ] || cannot "needs root (apt-get install slurm-wlm munge, and slurmd runs as root)"
missing=()
for p in slurm-wlm munge; do dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p"); done
if [ ${#missing[@]} -gt 0 ]; then
  say "installing ${missing[*]}"
  { apt-get update -qq &&
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq -o DPkg::Lock::Timeout=600 \
      --no-install-recommends "${missing[@]}"; } >/dev/null ||
    cannot "apt-get install ${missing[*]} failed"
fi
for tool in munged slurmctld slurmd sbatch squeue scontrol scancel sinfo setpriv; do
  command -v "$tool" >/dev/null || cannot "$tool not found after installing slurm-wlm and munge"
done
id munge >/dev/null 2>&1 || cannot "no munge user"
[ -s /etc/munge/munge.key ] || cannot "no /etc/munge/munge.key"
[ -x "$ROOT/build/granboltz" ] || fail "build/granboltz missing: run make build first"

# ------------------------------------------------------------------------------ start
WORK=$(mktemp -d /tmp/granboltz-slurm.XXXXXX)
chmod 755 "$WORK"  # munged runs as munge and must reach its socket folder
mkdir -p "$WORK"/{munge,state,spool,log}
chown munge:munge "$WORK/munge"
chmod 755 "$WORK/munge"  # munged wants the socket folder searchable by all
DAEMONS=()     # pids of what this script started, stopped in reverse order
SNAKEMAKE_PID=""
STATUS=1

cleanup() {
  local rc=$?
  set +e
  # Snakemake first (it submits nothing more once signalled), then the jobs it left.
  [ -n "$SNAKEMAKE_PID" ] && kill -TERM "$SNAKEMAKE_PID" 2>/dev/null
  if [ -n "${SLURM_CONF:-}" ] && [ ${#DAEMONS[@]} -ge 2 ]; then
    local jobs
    jobs=$(squeue -h -o %i 2>/dev/null)
    [ -n "$jobs" ] && scancel $jobs
    for _ in $(seq 60); do [ -z "$(squeue -h -o %i 2>/dev/null)" ] && break; sleep 0.5; done
  fi
  [ -n "$SNAKEMAKE_PID" ] && wait "$SNAKEMAKE_PID" 2>/dev/null
  for ((k = ${#DAEMONS[@]} - 1; k >= 0; k--)); do kill -TERM "${DAEMONS[k]}" 2>/dev/null; done
  for pid in "${DAEMONS[@]}"; do
    for _ in $(seq 100); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -0 "$pid" 2>/dev/null && kill -KILL "$pid"
    wait "$pid" 2>/dev/null
  done
  local left
  left=$(pgrep -f "$WORK" || true)
  [ -n "$left" ] && echo "test-slurm: processes still running: $left" >&2
  if [ "$rc" -ne 0 ] && [ "$rc" -ne "$CANNOT" ]; then
    echo "test-slurm: logs kept in $WORK" >&2
  elif [ "${KEEP:-0}" = 1 ]; then
    echo "test-slurm: kept $WORK"
  else
    rm -rf "$WORK"
  fi
  echo "test-slurm: everything started here is stopped ($(($(date +%s) - START)) s in all)"
  exit "$rc"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

HOST=$(hostname -s)
CPUS=$(nproc)
MEM_MB=$(($(awk '/MemTotal/ {print $2}' /proc/meminfo) / 1024 * 8 / 10))  # 80 % for jobs
PORT=$((20000 + ($$ % 5000) * 2))
export SLURM_CONF=$WORK/slurm.conf
cat >"$SLURM_CONF" <<EOF
# One-node test cluster of scripts/test-slurm.sh (no systemd, no cgroups, no accounting).
ClusterName=granboltz-test
SlurmctldHost=$HOST
SlurmctldPort=$PORT
SlurmdPort=$((PORT + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$WORK/munge/munge.socket
StateSaveLocation=$WORK/state
SlurmdSpoolDir=$WORK/spool
SlurmctldPidFile=$WORK/slurmctld.pid
SlurmdPidFile=$WORK/slurmd.pid
SlurmctldLogFile=$WORK/log/slurmctld.log
SlurmdLogFile=$WORK/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
ReturnToService=2
MpiDefault=none
KillWait=30
NodeName=$HOST CPUs=$CPUS RealMemory=$MEM_MB State=UNKNOWN
PartitionName=test Nodes=$HOST Default=YES MaxTime=INFINITE State=UP
EOF

say "starting munged, slurmctld, slurmd ($HOST, $CPUS CPUs, $MEM_MB MB, ports $PORT-$((PORT + 1)), $WORK)"
setpriv --reuid=munge --regid=munge --init-groups /usr/sbin/munged --foreground \
  --socket="$WORK/munge/munge.socket" --log-file="$WORK/munge/munged.log" \
  --pid-file="$WORK/munge/munged.pid" --seed-file="$WORK/munge/munged.seed" 2>/dev/null &
DAEMONS+=($!)
for _ in $(seq 50); do [ -S "$WORK/munge/munge.socket" ] && break; sleep 0.1; done
[ -S "$WORK/munge/munge.socket" ] || cannot "munged did not start: $(tail -n 3 "$WORK/munge/munged.log" 2>/dev/null)"
slurmctld -D -f "$SLURM_CONF" >"$WORK/log/slurmctld.stderr" 2>&1 &
DAEMONS+=($!)
slurmd -D -f "$SLURM_CONF" >"$WORK/log/slurmd.stderr" 2>&1 &
DAEMONS+=($!)
state=""
for _ in $(seq 120); do
  state=$(sinfo -h -N -o %t 2>/dev/null | head -n 1)
  [ "$state" = idle ] && break
  sleep 0.5
done
[ "$state" = idle ] || cannot "the node is not idle after 60 s (state '${state}'); slurmctld log: \
$(tail -n 3 "$WORK/log/slurmctld.log" 2>/dev/null | tr '\n' ' ') slurmd log: \
$(tail -n 3 "$WORK/log/slurmd.log" 2>/dev/null | tr '\n' ' ')"
say "node $HOST idle after $(($(date +%s) - START)) s"

# ------------------------------------------------------------------------------ workflow runs
# Paths in the config are relative to the repository: point them here from the run folders.
SNAKE=(snakemake --snakefile "$ROOT/workflow/Snakefile" --configfile "$PROFILE_CONFIG" --notemp
  --config granboltz="$ROOT/build/granboltz" published="$ROOT/config/published")

say "local run of ${TARGETS[*]} into $WORK/local"
t0=$(date +%s)
"${SNAKE[@]}" --directory "$WORK/local" --cores "$CPUS" "${TARGETS[@]}" \
  >"$WORK/log/local.log" 2>&1 || fail "local run failed (see $WORK/log/local.log)"
say "local run: $(($(date +%s) - t0)) s"

# Through the profile: partition and memory overridden for the test node; checkpoints every
# 10 minutes (never due here: only the preemption below writes one).
say "SLURM run of the same targets into $WORK/slurm (--profile workflow/profiles/slurm)"
t0=$(date +%s)
"${SNAKE[@]}" checkpoint_seconds=600 --directory "$WORK/slurm" \
  --profile "$ROOT/workflow/profiles/slurm" \
  --default-resources mem_mb=1000 runtime=30 partition=test --latency-wait 5 \
  "${TARGETS[@]}" >"$WORK/log/slurm.log" 2>&1 &
SNAKEMAKE_PID=$!

# Preempt the first shard job once its simulator runs (its temporary output exists) and has
# ensembles in progress: SIGTERM to the job as SLURM sends it before preempting.
tmp="" job=""
for _ in $(seq 1200); do
  kill -0 "$SNAKEMAKE_PID" 2>/dev/null || break
  tmp=$(compgen -G "$WORK/slurm/results/grw05/*/N=*/n=*/shard=*.h5.tmp.*" | head -n 1 || true)
  job=$(squeue -h -t R -n granboltz-grw05_shard -o %i | head -n 1)
  [ -n "$tmp" ] && [ -n "$job" ] && break
  sleep 0.25
done
[ -n "$tmp" ] && [ -n "$job" ] || fail "no shard job seen running (see $WORK/log/slurm.log)"
shard=${tmp%.tmp.*}
sleep 2
say "preempting job $job (${shard#"$WORK/slurm/"}): scancel --batch --signal=TERM $job"
scancel --batch --signal=TERM "$job"
for _ in $(seq 240); do  # the resubmitted job removes the checkpoint only when it completes
  [ -f "$shard.checkpoint" ] && break
  sleep 0.25
done
[ -f "$shard.checkpoint" ] || fail "no checkpoint $shard.checkpoint within 60 s of SIGTERM"
say "checkpoint written: ${shard#"$WORK/slurm/"}.checkpoint"
job_state=""
for _ in $(seq 240); do
  job_state=$(scontrol show job -o "$job" | grep -o 'JobState=[A-Z_]*')
  case "$job_state" in *=RUNNING | *=COMPLETING | *=SIGNALING) sleep 0.25 ;; *) break ;; esac
done
say "job $job ended: $job_state, $(scontrol show job -o "$job" | grep -o 'ExitCode=[0-9:]*');" \
  "cluster-status says: $("$ROOT/workflow/profiles/slurm/cluster-status.sh" "$job")"

wait "$SNAKEMAKE_PID" || { SNAKEMAKE_PID=""; fail "SLURM run failed (see $WORK/log/slurm.log)"; }
SNAKEMAKE_PID=""
say "SLURM run: $(($(date +%s) - t0)) s, $(grep -c 'Submitted job' "$WORK/log/slurm.log") submissions"

# ------------------------------------------------------------------------------ checks
resumed=$(/usr/bin/python3 -c 'import h5py, sys
v = h5py.File(sys.argv[1], "r")["provenance"].attrs["resumed_from_checkpoint"]
print(v.decode() if isinstance(v, bytes) else v)' "$shard")
[ "$resumed" = yes ] || fail "the resubmitted shard did not resume from its checkpoint"
say "the resubmitted job resumed from the checkpoint (${shard#"$WORK/slurm/"}: resumed_from_checkpoint = yes)"
[ ! -e "$shard.checkpoint" ] || fail "checkpoint left behind"

pairs=()
for f in "$WORK"/local/results/grw05/*/N=*/n=*/{run,shard=*}.h5 "${TARGETS[@]/#/$WORK/local/}"; do
  pairs+=("$f" "$WORK/slurm/${f#"$WORK/local/"}")
done
/usr/bin/python3 "$ROOT/scripts/compare_outputs.py" "${pairs[@]}" | sed "s|$WORK/||g" ||
  fail "SLURM and local results differ"
# ------------------------------------------------------------------------------ a study
# granboltz.study through the same profile, from a folder outside the repository: a study of two
# points is two sbatch jobs of the study's own Snakefile, a second call submits nothing, and the
# runs are identical to those of the same study run locally.
mkdir -p "$WORK/study"
cat >"$WORK/study/pair.yaml" <<'EOF'
study: pair
base: {model: dsmc, seed: 5, ensembles: 4, dsmc: {particles: 200, alpha: 0.8, beta: 1,
       kernel: {lambda: 1, C: 0.0795774715459477}, t_end: 2, observe_every: 0.5, steady_from: 1}}
grid: {dsmc.alpha: [0.5, 0.8]}
EOF
STUDY=(env GRANBOLTZ_BIN="$ROOT/build/granboltz" PYTHONPATH="$ROOT/src/python" /usr/bin/python3 -m granboltz.study)
SLURM_STUDY=(run pair.yaml --into slurm --profile "$ROOT/workflow/profiles/slurm"
  -- --default-resources mem_mb=1000 runtime=30 partition=test --latency-wait 5)
say "a study of 2 points through the profile into $WORK/study/slurm (python -m granboltz.study run --profile)"
t0=$(date +%s)
(cd "$WORK/study" && "${STUDY[@]}" "${SLURM_STUDY[@]}") >"$WORK/log/study.log" 2>&1 ||
  fail "the study through the profile failed (see $WORK/log/study.log)"
submitted=$(grep -c 'Submitted job' "$WORK/log/study.log" || true)
[ "$submitted" -eq 2 ] || fail "the study made $submitted submissions, not 2 (see $WORK/log/study.log)"
say "study through SLURM: $(($(date +%s) - t0)) s, $submitted submissions"
(cd "$WORK/study" && "${STUDY[@]}" "${SLURM_STUDY[@]}") >"$WORK/log/study-again.log" 2>&1 ||
  fail "the second study call failed (see $WORK/log/study-again.log)"
grep -q 'nothing to run' "$WORK/log/study-again.log" && ! grep -q 'Submitted job' "$WORK/log/study-again.log" ||
  fail "the second study call ran something (see $WORK/log/study-again.log)"
(cd "$WORK/study" && "${STUDY[@]}" run pair.yaml --into local --cores "$CPUS") >"$WORK/log/study-local.log" 2>&1 ||
  fail "the local study run failed (see $WORK/log/study-local.log)"
[ -d "$WORK/study/slurm/studies/pair/logs/slurm" ] || fail "no job logs in the study folder"
[ "$(cd "$WORK/study" && echo *)" = "local pair.yaml slurm" ] || fail "the study wrote outside its folders"
pairs=()
for f in "$WORK"/study/local/studies/pair/runs/*.h5; do pairs+=("$f" "$WORK/study/slurm/${f#"$WORK/study/local/"}"); done
[ ${#pairs[@]} -eq 4 ] || fail "the local study has $((${#pairs[@]} / 2)) runs, not 2"
/usr/bin/python3 "$ROOT/scripts/compare_outputs.py" "${pairs[@]}" | sed "s|$WORK/||g" ||
  fail "the study's runs through SLURM and local differ"
rows=$(cd "$WORK/study" && "${STUDY[@]}" table pair.yaml --into slurm --csv | wc -l) || fail "the study table failed"
[ "$rows" -eq 3 ] || fail "the study table has $rows lines, not a header and 2 rows"
say "the study's 2 points ran as SLURM jobs, a second call submitted nothing, runs identical to local"

say "PASSED: merged runs, shards and tables identical to the local run, one preempted job resumed," \
  "a study of 2 points through the profile"
STATUS=0
