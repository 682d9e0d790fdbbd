"""workflow/profiles/slurm without a cluster: the cluster-status script against stand-in sacct and
scontrol commands, and the job script as Snakemake formats and runs it (SIGTERM forwarding).
The profile against a live SLURM is `make test-slurm` (scripts/test-slurm.sh)."""

import os
import signal
import subprocess
import sys
import time

import pytest
import yaml

from conftest import ROOT

PROFILE = ROOT / "workflow" / "profiles" / "slurm"


def fake(tmp_path, name, stdout="", stderr="", code=0):
    """A command `name` on PATH that prints stdout/stderr and exits with code."""
    path = tmp_path / "bin" / name
    path.parent.mkdir(exist_ok=True)
    path.write_text(f"#!/bin/sh\nprintf '%s' '{stdout}'\nprintf '%s' '{stderr}' >&2\nexit {code}\n")
    path.chmod(0o755)


def status(tmp_path, jobid="42"):
    env = dict(os.environ, PATH=f"{tmp_path / 'bin'}:/usr/bin:/bin")
    out = subprocess.run([str(PROFILE / "cluster-status.sh"), jobid], env=env, text=True,
                         capture_output=True, check=True)
    return out.stdout.strip()


@pytest.mark.parametrize("state,expected", [
    ("COMPLETED", "success"), ("RUNNING", "running"), ("PENDING", "running"),
    ("COMPLETING", "running"), ("FAILED", "failed"), ("CANCELLED by 0", "failed"),
    ("TIMEOUT", "failed"), ("OUT_OF_MEMORY", "failed"), ("PREEMPTED", "failed"),
    ("NODE_FAIL", "failed"),
])
def test_cluster_status_reads_sacct(tmp_path, state, expected):
    fake(tmp_path, "sacct", stdout=state + "\n")
    fake(tmp_path, "scontrol", code=1)
    assert status(tmp_path, "42;cluster") == expected


@pytest.mark.parametrize("state,expected", [
    ("COMPLETED", "success"), ("RUNNING", "running"), ("FAILED", "failed"),
    ("CANCELLED", "failed"), ("TIMEOUT", "failed"),
])
def test_cluster_status_falls_back_to_scontrol_without_accounting(tmp_path, state, expected):
    fake(tmp_path, "sacct", stderr="Slurm accounting storage is disabled", code=1)
    fake(tmp_path, "scontrol", stdout=f"JobId=42 JobName=x UserId=root(0) JobState={state} Reason=None ExitCode=1:0")
    assert status(tmp_path) == expected


def test_cluster_status_of_a_purged_job_is_failed_and_of_a_silent_controller_running(tmp_path):
    fake(tmp_path, "sacct", code=1)
    fake(tmp_path, "scontrol", stderr="slurm_load_jobs error: Invalid job id specified", code=1)
    assert status(tmp_path) == "failed"
    fake(tmp_path, "scontrol", stderr="slurm_load_jobs error: Unable to contact slurm controller", code=1)
    assert status(tmp_path) == "running"


def test_profile_names_files_that_exist():
    cfg = yaml.safe_load((PROFILE / "config.yaml").read_text())
    for key in ("cluster-status", "jobscript"):
        assert (PROFILE / cfg[key]).is_file(), key
        assert os.access(PROFILE / cfg[key], os.X_OK), key
    assert cfg["restart-times"] >= 1  # a preempted job must be resubmitted


def run_jobscript(tmp_path, exec_job):
    """The profile's job script, formatted as Snakemake does, started in the background."""
    script = tmp_path / "job.sh"
    script.write_text((PROFILE / "jobscript.sh").read_text().format(properties="{}", exec_job=exec_job))
    script.chmod(0o755)
    return subprocess.Popen([str(script)], start_new_session=True)


# Stands for Snakemake (ignores SIGTERM, as the job script arranges) running the simulator (a
# handler that writes a file, like a checkpoint, and exits with 143).
SIMULATOR = (f"{sys.executable} -c 'import signal, sys, time, pathlib\n"
             "def stop(*_):\n"
             "    pathlib.Path(sys.argv[1]).write_text(\"checkpoint\")\n"
             "    sys.exit(143)\n"
             "signal.signal(signal.SIGTERM, stop)\n"
             "pathlib.Path(sys.argv[2]).touch()\n"
             "time.sleep(20)' {ckpt} {started}")


def wait_for(path):
    for _ in range(200):
        if path.exists():
            return
        time.sleep(0.05)
    raise AssertionError(f"{path} never appeared")


def test_jobscript_passes_sigterm_to_the_simulator_and_fails_the_job(tmp_path):
    ckpt, started = tmp_path / "ckpt", tmp_path / "started"
    job = run_jobscript(tmp_path, "sleep 0.1 && " + SIMULATOR.format(ckpt=ckpt, started=started))
    try:
        wait_for(started)
        job.send_signal(signal.SIGTERM)  # sbatch --signal=B:TERM@...: the batch shell only
        assert job.wait(timeout=10) == 143
        assert ckpt.read_text() == "checkpoint"
    finally:  # nothing left running, whatever failed
        try:
            os.killpg(job.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        job.wait()


def test_jobscript_passes_the_exit_status_of_a_job_left_alone(tmp_path):
    assert run_jobscript(tmp_path, "true").wait(timeout=10) == 0
    assert run_jobscript(tmp_path, "exit 3").wait(timeout=10) == 3
