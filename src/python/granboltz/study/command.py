"""Parameter studies: one base config, a grid of values, one simulator run per grid point.

A study file names the study, its base config and the grid (dotted keys into the config, each a
non-empty list of values; the points are their Cartesian product):

    study: scan
    base: {model: dsmc, seed: 5, ensembles: 4, dsmc: {particles: 500, alpha: 0.8, beta: 1,
           kernel: {lambda: 1, C: 0.0795774715459477}, t_end: 4, observe_every: 0.5, steady_from: 1}}
    grid: {dsmc.alpha: [0.5, 0.8], dsmc.kernel.lambda: [0.0, 1.0]}

    python -m granboltz.study run scan.yaml [--cores N] [--profile workflow/profiles/slurm] [--into DIR]
                                            [--max-points N] [-- SNAKEMAKE ARGS]
    python -m granboltz.study table scan.yaml [--into DIR]

`run` writes, under the current directory (or DIR), the folder studies/<study>/ with
    study.yaml          the study file as read
    points/<hash>.yaml  each point's full config; <hash>: the first 12 hex digits of the sha256 of
                        its canonical JSON (sorted keys, no spaces), so equal configs share a run
    index.csv           hash and one column per grid key, one row per point of the current grid
    runs/<hash>.h5      each point's output, made by Snakemake (study.smk, shipped here) calling
                        the granboltz binary; logs/<hash>.log its output
    damaged/            runs (and other files of the folder) that were damaged, foreign or not
                        regular files, moved aside before their point was run again
and runs only the points without a sound run of their own: a second call runs nothing, a grid
with a new value runs only the new points (the old points' files stay, whether or not the grid
still has them), and a run that is damaged (granboltz verify), of another point, or not a
regular file is moved to damaged/ and made again. A point file is written only when its content
changes, so an unchanged point never looks newer than its run. Nothing outside the study folder
is written (Snakemake's .snakemake/ and, with the SLURM profile, logs/slurm/ are inside it too),
and no symbolic link inside it is followed.

Everything is checked before anything is written: the study file (a regular UTF-8 file of at
most 1 MiB; at most 100 000 YAML nodes, also with aliases expanded; at most 64 levels; no key
given twice; finite numbers), the number of points (at most MAX_POINTS unless max_points /
--max-points says more) and every point's config, by the simulator's own parser.

    from granboltz.study import Study, run     # Study: granboltz.study.table (also granboltz.Study)
    run("scan.yaml", cores=2)                  # the same as the command line `run`
    Study("studies/scan").table()              # pandas DataFrame, one row per point

The simulator: $GRANBOLTZ_BIN, else build/granboltz of the repository this package is in, else
`granboltz` on PATH.  Errors in the study file or its folder (and runs missing or damaged in
table()) raise StudyError, whose message is one line; the command line prints it and exits with
status 2. One runner at a time per study folder: a second is refused while the first (or its
Snakemake) lives; a runner stopped by SIGTERM or SIGINT stops its Snakemake and the simulator
first, and the next `run` resumes, removing a Snakemake lock that no living runner holds.
"""

import argparse
import csv
import io
import signal
import stat
import subprocess
import sys

import yaml

from .folder import LOCK_NAME, move_aside, runner_lock, write_if_changed, check_folder
from .grid import full_grid
from .runs import check_runs, identity_problem, not_regular, run_difference, verify_runs
from .snakemake import SNAKEFILE, Stopped, unlock_stale, run_snakemake, snakemake_command
from .spec import (MAX_NAME, MAX_POINTS, cell_text, check_point_list, canonical, check_points, check_study, expand,
                         find_binary, load_study, point_hash, point_text, run_config, study_folder)
from .safe_yaml import MAX_BYTES, MAX_DEPTH, MAX_NODES, StudyError, lstat, one_line, show, load_yaml

# The parts live in study_yaml (reading), study_spec (the study file and its points), study_folder,
# study_runs (is a run sound and its point's), study_snakemake and study_table (Study); their
# public names are this module's too.
__all__ = ["MAX_BYTES", "MAX_DEPTH", "MAX_NAME", "MAX_NODES", "MAX_POINTS", "LOCK_NAME", "SNAKEFILE",
           "StudyError", "canonical", "check_folder", "check_points", "check_runs", "check_study", "expand",
           "find_binary", "identity_problem", "load_study", "load_yaml", "main", "not_regular", "point_hash",
           "point_text", "prepare", "run", "run_config", "run_difference", "run_snakemake", "snakemake_command",
           "study_folder", "verify_runs"]


def _plan(study_file, into, max_points):
    """Everything checked, nothing written: (spec, folder, points, {hash: point text})."""
    spec = load_study(study_file, max_points)
    folder = study_folder(spec, into)
    points = expand(spec)
    checked = check_point_list(points, study_file)
    check_folder(folder)
    return spec, folder, points, checked


def _write_folder(spec, folder, points, checked):
    for h, _, _ in points:
        write_if_changed(folder / "points" / f"{h}.yaml", checked[h][0], folder)
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    grid = full_grid(spec)
    writer.writerow(["hash", *grid])
    for h, values, _ in points:
        writer.writerow([h, *(cell_text(values[k]) for k in grid)])
    write_if_changed(folder / "index.csv", out.getvalue(), folder)
    write_if_changed(folder / "study.yaml", yaml.safe_dump(spec, sort_keys=False), folder)


def prepare(study_file, into=None, max_points=MAX_POINTS):
    """Expand the study file, check every point, and write its folder (study.yaml, points/,
    index.csv); returns (folder, points) with points as expand() gives them."""
    spec, folder, points, checked = _plan(study_file, into, max_points)
    with runner_lock(folder):
        _write_folder(spec, folder, points, checked)
    return folder, points


def run(study_file, cores=None, profile=None, into=None, quiet=False, extra=(), max_points=MAX_POINTS):
    """Write the study folder and run the points without a sound run of their own (Snakemake, with
    `cores` local cores, default 1, or through the Snakemake `profile` folder, e.g.
    workflow/profiles/slurm). Runs that are damaged, of another point or not regular files are
    moved to damaged/ and made again. max_points: the most points the grid may have (None: no
    limit). Returns the Study. Raises StudyError for a bad study file or folder, no simulator or
    another runner of the study alive (before anything is written), subprocess.CalledProcessError
    when Snakemake fails. SIGTERM and SIGINT stop Snakemake and the simulator first (run_snakemake)."""
    from .table import Study

    if max_points is not None and (isinstance(max_points, bool) or not isinstance(max_points, int) or max_points < 1):
        raise StudyError(f"max_points = {show(max_points, 40)}: must be an integer >= 1 (or None: no limit)")
    spec, folder, points, checked = _plan(study_file, into, max_points)
    binary = find_binary()
    say = (lambda msg: None) if quiet else (lambda msg: print(f"granboltz.study: {msg}", flush=True))
    with runner_lock(folder) as lock_fd:
        if lock_fd is not None:
            unlock_stale(folder, binary, quiet)
        _write_folder(spec, folder, points, checked)
        problems = check_runs(folder, points, binary, {h: c for h, (_, c) in checked.items()})
        for h, problem in problems.items():
            for path in (folder / "runs" / f"{h}.h5", folder / "logs" / f"{h}.log"):
                st = lstat(path)
                if st is not None and (path.suffix == ".h5" or not stat.S_ISREG(st.st_mode)):
                    moved = move_aside(path, folder)
                    if path.suffix == ".h5":
                        say(f"{folder.name}: run {h} is {problem}: moved to {moved.relative_to(folder)}")
        if not problems:
            say(f"{folder.name}: all {len(points)} points have runs; nothing to run")
            return Study(folder)
        missing = [h for h, _, _ in points if h in problems]
        say(f"{folder.name}: running {len(missing)} of {len(points)} points in {folder}")
        cmd = snakemake_command(folder, [f"runs/{h}.h5" for h in missing], binary, cores, profile, extra)
        status = run_snakemake(cmd, folder, lock_fd, quiet)
    if status != 0:
        raise subprocess.CalledProcessError(status, cmd)
    return Study(folder)


def __getattr__(name):
    # granboltz.study.Study: the reader lives in study.table (pandas only when a table is made)
    if name == "Study":
        from .table import Study

        return Study
    raise AttributeError(f"module 'granboltz.study' has no attribute {name!r}")


# ------------------------------------------------------------------------------ command line
def main(argv=None):
    """The command line: python -m granboltz.study run|table STUDY.yaml ...; returns the exit status."""
    parser = argparse.ArgumentParser(prog="python -m granboltz.study",
                                     description="Parameter studies of granboltz runs (see docs/python.md, Studies).")
    sub = parser.add_subparsers(dest="command", required=True)
    p_run = sub.add_parser("run", help="write the study folder and run the points without a sound run",
                           epilog="Arguments after -- go to Snakemake, e.g. -- --default-resources partition=NAME.")
    p_run.add_argument("study", help="the study file (YAML: study, base, grid)")
    p_run.add_argument("--cores", type=int, help="local cores for Snakemake (default 1; with --profile as the profile says)")
    p_run.add_argument("--profile", help="a Snakemake profile folder, e.g. workflow/profiles/slurm")
    p_run.add_argument("--into", help="write studies/<study>/ under this folder (default: the current one)")
    p_run.add_argument("--max-points", type=int, default=MAX_POINTS, metavar="N",
                       help=f"refuse a grid of more than N points (default {MAX_POINTS})")
    p_table = sub.add_parser("table", help="print the table of a study's runs")
    p_table.add_argument("study", help="the study file or its folder studies/<study>")
    p_table.add_argument("--into", help="the folder that holds studies/ (default: the current one)")
    p_table.add_argument("--csv", action="store_true", help="print CSV instead of the aligned table")
    p_table.add_argument("--replicas", action="store_true", help="one row per replica (no aggregation)")
    p_status = sub.add_parser("status", help="which points have a sound run, which are missing or damaged "
                                             "(exit status 3 while any is)")
    p_status.add_argument("study", help="the study file or its folder studies/<study>")
    p_status.add_argument("--into", help="the folder that holds studies/ (default: the current one)")
    argv = list(sys.argv[1:] if argv is None else argv)
    extra = argv[argv.index("--") + 1:] if "--" in argv else []  # run ... -- SNAKEMAKE ARGS
    args = parser.parse_args(argv[:len(argv) - len(extra) - 1] if "--" in argv else argv)
    if extra and args.command != "run":
        parser.error("only run passes arguments after -- to Snakemake")
    if args.command == "run" and args.max_points < 1:
        parser.error(f"argument --max-points: must be >= 1 (got {args.max_points})")

    def stopped(signum, frame):
        raise Stopped

    previous = signal.signal(signal.SIGTERM, stopped) if signal.getsignal(signal.SIGTERM) == signal.SIG_DFL else None
    try:
        if args.command == "run":
            run(args.study, cores=args.cores, profile=args.profile, into=args.into, extra=extra,
                max_points=args.max_points)
        elif args.command == "status":
            from .table import Study

            return _status(Study(args.study, into=args.into))
        else:
            from .table import Study

            table = Study(args.study, into=args.into).table(aggregate=False if args.replicas else None)
            if args.csv:
                table.to_csv(sys.stdout, index=False)
            else:
                import pandas as pd

                with pd.option_context("display.max_rows", None, "display.max_columns", None, "display.width", 200):
                    print(table.to_string(index=False))
    except StudyError as e:
        print(f"granboltz.study: error: {one_line(e, 2000)}", file=sys.stderr)  # a path may hold a newline
        return 2
    except subprocess.CalledProcessError as e:
        print(f"granboltz.study: error: Snakemake failed (status {e.returncode}); see its output above and the "
              "simulator's in studies/<study>/logs/", file=sys.stderr)
        return 1
    except (Stopped, KeyboardInterrupt) as e:
        name = "SIGTERM" if isinstance(e, Stopped) else "SIGINT"
        print(f"granboltz.study: stopped by {name} (Snakemake and the simulator too); run again to resume",
              file=sys.stderr)
        return 128 + (signal.SIGTERM if isinstance(e, Stopped) else signal.SIGINT)
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)
    return 0


def _status(study):
    """Prints one line per point (hash, grid values, ok or what is wrong) and a summary; the
    exit status: 0 when every point has a sound run, 3 otherwise."""
    problems = study.problems()
    for h, values in study.points:
        state = problems.get(h, "ok")
        print(f"{h}  {one_line(', '.join(f'{k}={cell_text(v)}' for k, v in values.items()), 120)}  {one_line(state, 160)}")
    kinds = {}
    for p in problems.values():
        kind = "missing" if p == "missing" else "damaged" if p.startswith("damaged") else "other"
        kinds[kind] = kinds.get(kind, 0) + 1
    detail = ", ".join(f"{n} {k}" if k != "other" else f"{n} not its point's or not a file" for k, n in kinds.items())
    print(f"{study.name}: {len(study.points) - len(problems)} of {len(study.points)} points have a sound run"
          + (f" ({detail})" if detail else ""))
    return 3 if problems else 0
