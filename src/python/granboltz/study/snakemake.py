"""Snakemake for a parameter study (granboltz.study): the command that makes a study's runs
with the package's Snakefile (study.smk), run in a process group of its own with the runner's
signals passed on, its cache kept in the study folder, and a lock left by a killed Snakemake
removed."""

import contextlib
import os
import pathlib
import signal
import subprocess
import sys
import threading

from .safe_yaml import StudyError, one_line

SNAKEFILE = pathlib.Path(__file__).resolve().with_name("study.smk")
_PYTHON = "/usr/bin/python3"


def _python():
    return _PYTHON if os.access(_PYTHON, os.X_OK) else sys.executable


def snakemake_environment(folder):
    """The environment of Snakemake: its cache (a copy of the Snakefile it keeps in
    ~/.cache/snakemake otherwise) in the study folder's .snakemake/, so that nothing outside the
    study folder is written."""
    return dict(os.environ, XDG_CACHE_HOME=str(folder / ".snakemake" / "cache"))


def snakemake_command(folder, targets, binary, cores=None, profile=None, extra=()):
    """The Snakemake call that makes `targets` (paths relative to the study folder)."""
    cmd = [_python(), "-m", "snakemake",
           "--snakefile", str(SNAKEFILE), "--directory", str(folder),
           "--config", f"granboltz={binary}",
           "--rerun-triggers", "mtime",  # only a point file newer than its run (it is rewritten only when changed)
           "--rerun-incomplete"]  # a run a killed Snakemake left marked: remade (runs are checked before)
    if profile is not None:  # a folder (made absolute: Snakemake runs in the study folder) or a profile name
        cmd += ["--profile", str(pathlib.Path(profile).absolute()) if pathlib.Path(profile).exists() else profile]
    if cores is not None or profile is None:
        cmd += ["--cores", str(cores if cores is not None else 1)]
    return cmd + list(extra) + list(targets)


def unlock_stale(folder, binary, quiet):
    """Remove a Snakemake lock left by a Snakemake that was killed: called with the runner lock
    held, so no runner of this study, and no Snakemake one started, is alive."""
    locks = folder / ".snakemake" / "locks"
    if not (locks.is_dir() and any(locks.iterdir())):
        return
    cmd = [_python(), "-m", "snakemake", "--snakefile", str(SNAKEFILE), "--directory", str(folder),
           "--config", f"granboltz={binary}", "--unlock", "--cores", "1"]
    out = subprocess.run(cmd, cwd=folder, capture_output=True, text=True, env=snakemake_environment(folder))
    if out.returncode != 0:
        raise StudyError(f"{folder}: cannot remove a stale Snakemake lock (snakemake --unlock exited "
                         f"{out.returncode}: {one_line((out.stderr.strip().splitlines() or [''])[-1], 120)})")
    if not quiet:
        print(f"granboltz.study: {folder.name}: removed the lock of a Snakemake that no longer runs", flush=True)


def _snakemake_preexec():
    """The preexec function of Snakemake: a process group of its own (its jobs join it), and
    SIGTERM to it when the runner dies, even by SIGKILL (Linux's PR_SET_PDEATHSIG), so that it
    starts no more points and ends; it exits at once if the runner is gone already."""
    try:
        import ctypes

        prctl = ctypes.CDLL(None, use_errno=True).prctl  # looked up here: nothing is imported after fork
    except (OSError, AttributeError):
        prctl = None
    parent = os.getpid()

    def preexec():
        os.setpgid(0, 0)
        if prctl is not None:
            prctl(1, int(signal.SIGTERM))  # 1: PR_SET_PDEATHSIG
            if os.getppid() != parent:
                os._exit(1)
    return preexec


class Stopped(Exception):
    """The command line's SIGTERM: becomes exit status 143 with one line."""


def run_snakemake(cmd, folder, lock_fd=None, quiet=False):
    """Run Snakemake in a process group of its own; returns its exit status. While it runs, a
    SIGTERM or SIGINT to this process is passed on to the group (the first as SIGTERM: local
    jobs stop, the simulator removing its temporary files or writing a final checkpoint; a second
    as SIGINT: Snakemake cancels cluster jobs too; a third as SIGKILL), Snakemake is waited for,
    and what is left of its group is stopped. Then SIGINT raises KeyboardInterrupt and SIGTERM
    goes to the handler that was there before (the default ends the process)."""
    received = []
    group = []
    ladder = (signal.SIGTERM, signal.SIGINT, signal.SIGKILL)

    def forward(signum, frame):
        received.append(signum)
        if group:
            with contextlib.suppress(ProcessLookupError, PermissionError):
                os.killpg(group[0], ladder[min(len(received), 3) - 1])

    handlers = {}
    if threading.current_thread() is threading.main_thread():
        for sig in (signal.SIGTERM, signal.SIGINT):
            if signal.getsignal(sig) not in (signal.SIG_IGN, None):
                handlers[sig] = signal.signal(sig, forward)
    try:
        proc = subprocess.Popen(cmd, cwd=folder, pass_fds=() if lock_fd is None else (lock_fd,),
                                preexec_fn=_snakemake_preexec(), env=snakemake_environment(folder),
                                stdout=subprocess.DEVNULL if quiet else None,
                                stderr=subprocess.DEVNULL if quiet else None)
        group.append(proc.pid)
        if received:  # a signal before the group existed
            forward(received.pop(), None)
        os.waitid(os.P_PID, proc.pid, os.WEXITED | os.WNOWAIT)  # not reaped yet: its group id stays its own
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.killpg(proc.pid, signal.SIGTERM)  # jobs of a Snakemake that died without stopping them
        status = proc.wait()
    finally:
        for sig, previous in handlers.items():
            signal.signal(sig, previous)
    if received:
        if signal.SIGINT in received and signal.SIGTERM not in received:
            raise KeyboardInterrupt
        previous = handlers.get(signal.SIGTERM, signal.SIG_DFL)
        if previous == signal.SIG_DFL:
            signal.raise_signal(signal.SIGTERM)
        elif callable(previous):
            previous(signal.SIGTERM, None)
    return status
