"""Parameter studies: one base config, a grid of values, one simulator run per grid point.

A study file names the study, its base config and the grid (dotted keys into the config, each a
non-empty list of values; the points are their Cartesian product):

    study: scan
    base: {model: dsmc, seed: 5, ensembles: 4, dsmc: {particles: 500, alpha: 0.8, beta: 1,
           kernel: {lambda: 1, C: 0.0795774715459477}, t_end: 4, observe_every: 0.5, steady_from: 1}}
    grid: {dsmc.alpha: [0.5, 0.8], dsmc.kernel.lambda: [0.0, 1.0]}

    python -m granboltz.study run scan.yaml [--cores N] [--profile workflow/profiles/slurm] [--into DIR] [-- SNAKEMAKE ARGS]
    python -m granboltz.study table scan.yaml [--into DIR]

`run` writes, under the current directory (or DIR), the folder studies/<study>/ with
    study.yaml          the study file as read
    points/<hash>.yaml  each point's full config; <hash>: the first 12 hex digits of the sha256 of
                        its canonical JSON (sorted keys, no spaces), so equal configs share a run
    index.csv           hash and one column per grid key, one row per point of the current grid
    runs/<hash>.h5      each point's output, made by Snakemake (study.smk, shipped here) calling
                        the granboltz binary; logs/<hash>.log its output
and runs only the points whose run is missing: a second call runs nothing, a grid with a new
value runs only the new points (the old points' files stay, whether or not the grid still has
them). A point file is written only when its content changes, so an unchanged point never looks
newer than its run. Nothing outside the study folder is written (Snakemake's .snakemake/ and, with
the SLURM profile, logs/slurm/ are inside it too).

    from granboltz.study import Study, run     # Study: granboltz.study_table (also granboltz.Study)
    run("scan.yaml", cores=2)                  # the same as the command line `run`
    Study("studies/scan").table()              # pandas DataFrame, one row per point

The simulator: $GRANBOLTZ_BIN, else build/granboltz of the repository this package is in, else
`granboltz` on PATH.  Errors in the study file (and missing runs in table()) raise StudyError,
whose message is one line; the command line prints it and exits with status 2.
"""

import argparse
import copy
import csv
import hashlib
import io
import itertools
import json
import os
import pathlib
import re
import shutil
import subprocess
import sys

import yaml

SNAKEFILE = pathlib.Path(__file__).resolve().with_name("study.smk")
_NAME = re.compile(r"[A-Za-z0-9_-]+")
_PYTHON = "/usr/bin/python3"


class StudyError(ValueError):
    """A study file that cannot be used, a simulator that cannot be found, or missing runs."""


# ------------------------------------------------------------------------------ the study file
def load_study(path):
    """The study file at `path` checked: {"study": name, "base": dict, "grid": {key: [values]}}."""
    path = pathlib.Path(path)
    try:
        text = path.read_text()
    except OSError as e:
        raise StudyError(f"{path}: cannot read the study file ({e.strerror or e})") from None
    try:
        spec = yaml.safe_load(text)
    except yaml.YAMLError as e:
        where = getattr(e, "problem_mark", None)
        at = f" (line {where.line + 1})" if where is not None else ""
        raise StudyError(f"{path}: not YAML{at}: {getattr(e, 'problem', None) or e}".replace("\n", " ")) from None
    return check_study(spec, path)


def check_study(spec, path="study"):
    """The study mapping checked (see load_study); StudyError with a one-line message otherwise."""
    if not isinstance(spec, dict):
        raise StudyError(f"{path}: a study file is a mapping with keys study, base and grid")
    unknown = sorted(set(spec) - {"study", "base", "grid"})
    if unknown:
        raise StudyError(f"{path}: unknown key {unknown[0]!r} (allowed: study, base, grid)")
    name = spec.get("study")
    if not isinstance(name, str) or not _NAME.fullmatch(name):
        raise StudyError(f"{path}: study must be a name of letters, digits, _ and - (got {name!r})")
    base = spec.get("base")
    if not isinstance(base, dict) or not base:
        raise StudyError(f"{path}: base must be a config mapping (model, seed, ensembles, ...)")
    grid = spec.get("grid")
    if not isinstance(grid, dict) or not grid:
        raise StudyError(f"{path}: grid must be a non-empty mapping of dotted keys to lists of values")
    for key, values in grid.items():
        if not isinstance(key, str) or not key or any(not part for part in key.split(".")):
            raise StudyError(f"{path}: grid key {key!r} is not a dotted config key such as dsmc.alpha")
        if not isinstance(values, list) or not values:
            raise StudyError(f"{path}: grid.{key} must be a non-empty list of values (got {values!r})")
        if len({canonical(v) for v in values}) != len(values):
            raise StudyError(f"{path}: grid.{key} repeats a value")
        _set(copy.deepcopy(base), key, values[0], path)  # a key that cannot be set fails here
    return {"study": name, "base": base, "grid": grid}


def _set(config, key, value, path="study"):
    """Set the dotted `key` of `config` to `value`, creating mappings on the way."""
    node, parts = config, key.split(".")
    for i, part in enumerate(parts[:-1]):
        child = node.setdefault(part, {})
        if not isinstance(child, dict):
            raise StudyError(f"{path}: grid key {key!r}: {'.'.join(parts[:i + 1])} is not a mapping in base")
        node = child
    node[parts[-1]] = copy.deepcopy(value)
    return config


def _get(config, key):
    node = config
    for part in key.split("."):
        node = node[part]
    return node


def canonical(value):
    """The canonical JSON of a config (sorted keys, no spaces): what the point hash is taken of."""
    return json.dumps(value, sort_keys=True, separators=(",", ":"), ensure_ascii=False, allow_nan=False)


def point_hash(config):
    """The first 12 hex digits of the sha256 of the config's canonical JSON."""
    return hashlib.sha256(canonical(config).encode()).hexdigest()[:12]


def expand(spec):
    """The points of a checked study: [(hash, {grid key: value}, config)] in grid order (the
    last key varies fastest)."""
    keys = list(spec["grid"])
    points, seen = [], set()
    for values in itertools.product(*(spec["grid"][k] for k in keys)):
        config = copy.deepcopy(spec["base"])
        for key, value in zip(keys, values):
            _set(config, key, value)
        h = point_hash(config)
        if h not in seen:  # two grid values that give one config (e.g. 1 and 1.0 never do: JSON keeps them apart)
            seen.add(h)
            points.append((h, dict(zip(keys, values)), config))
    return points


# ------------------------------------------------------------------------------ files
def _write_if_changed(path, text):
    """Write `text` to `path` (atomically) only when the file does not already hold it."""
    path = pathlib.Path(path)
    try:
        if path.read_text() == text:
            return False
    except OSError:
        pass
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    tmp.write_text(text)
    os.replace(tmp, path)
    return True


def _cell(value):
    return value if isinstance(value, str) else canonical(value)


def study_folder(spec, into=None):
    """The folder of a checked study: studies/<study> under `into` (default the current directory)."""
    return pathlib.Path(into or ".").absolute() / "studies" / spec["study"]


def prepare(study_file, into=None):
    """Expand the study file and write its folder (study.yaml, points/, index.csv); returns
    (folder, points) with points as expand() gives them."""
    spec = load_study(study_file)
    folder = study_folder(spec, into)
    points = expand(spec)
    for h, _, config in points:
        _write_if_changed(folder / "points" / f"{h}.yaml", yaml.safe_dump(config, sort_keys=True))
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(["hash", *spec["grid"]])
    for h, values, _ in points:
        writer.writerow([h, *(_cell(values[k]) for k in spec["grid"])])
    _write_if_changed(folder / "index.csv", out.getvalue())
    _write_if_changed(folder / "study.yaml", yaml.safe_dump(spec, sort_keys=False))
    return folder, points


def find_binary():
    """The granboltz simulator: $GRANBOLTZ_BIN, else build/granboltz of this source tree, else
    `granboltz` on PATH (absolute path); StudyError if none is executable."""
    env = os.environ.get("GRANBOLTZ_BIN")
    if env:
        if os.access(env, os.X_OK) and os.path.isfile(env):
            return str(pathlib.Path(env).absolute())
        raise StudyError(f"GRANBOLTZ_BIN={env} is not an executable file")
    tree = pathlib.Path(__file__).resolve().parents[3] / "build" / "granboltz"
    if os.access(tree, os.X_OK) and tree.is_file():
        return str(tree)
    found = shutil.which("granboltz")
    if found:
        return str(pathlib.Path(found).absolute())
    raise StudyError(f"no granboltz simulator: set GRANBOLTZ_BIN, build {tree} (make build) or put granboltz on PATH")


def snakemake_command(folder, targets, binary, cores=None, profile=None, extra=()):
    """The Snakemake call that makes `targets` (paths relative to the study folder)."""
    cmd = [_PYTHON if os.access(_PYTHON, os.X_OK) else sys.executable, "-m", "snakemake",
           "--snakefile", str(SNAKEFILE), "--directory", str(folder),
           "--config", f"granboltz={binary}",
           "--rerun-triggers", "mtime"]  # only a point file newer than its run (it is rewritten only when changed)
    if profile is not None:  # a folder (made absolute: Snakemake runs in the study folder) or a profile name
        cmd += ["--profile", str(pathlib.Path(profile).absolute()) if pathlib.Path(profile).exists() else profile]
    if cores is not None or profile is None:
        cmd += ["--cores", str(cores if cores is not None else 1)]
    return cmd + list(extra) + list(targets)


def run(study_file, cores=None, profile=None, into=None, quiet=False, extra=()):
    """Write the study folder and run the points whose runs/<hash>.h5 is missing (Snakemake, with
    `cores` local cores, default 1, or through the Snakemake `profile` folder, e.g.
    workflow/profiles/slurm). Returns the Study. Raises StudyError for a bad study file or no
    simulator, subprocess.CalledProcessError when Snakemake fails."""
    from .study_table import Study

    folder, points = prepare(study_file, into)
    missing = [h for h, _, _ in points if not (folder / "runs" / f"{h}.h5").is_file()]
    say = (lambda msg: None) if quiet else (lambda msg: print(f"granboltz.study: {msg}", flush=True))
    if not missing:
        say(f"{folder.name}: all {len(points)} points have runs; nothing to run")
        return Study(folder)
    binary = find_binary()
    say(f"{folder.name}: running {len(missing)} of {len(points)} points in {folder}")
    cmd = snakemake_command(folder, [f"runs/{h}.h5" for h in missing], binary, cores, profile, extra)
    subprocess.run(cmd, check=True, cwd=folder, stdout=subprocess.DEVNULL if quiet else None,
                   stderr=subprocess.DEVNULL if quiet else None)
    return Study(folder)


def __getattr__(name):
    # granboltz.study.Study: the reader lives in study_table (pandas only when a table is made)
    if name == "Study":
        from .study_table import Study

        return Study
    raise AttributeError(f"module 'granboltz.study' has no attribute {name!r}")


# ------------------------------------------------------------------------------ command line
def main(argv=None):
    """The command line: python -m granboltz.study run|table STUDY.yaml ...; returns the exit status."""
    parser = argparse.ArgumentParser(prog="python -m granboltz.study",
                                     description="Parameter studies of granboltz runs (see docs/python.md, Studies).")
    sub = parser.add_subparsers(dest="command", required=True)
    p_run = sub.add_parser("run", help="write the study folder and run the points without a run",
                           epilog="Arguments after -- go to Snakemake, e.g. -- --default-resources partition=NAME.")
    p_run.add_argument("study", help="the study file (YAML: study, base, grid)")
    p_run.add_argument("--cores", type=int, help="local cores for Snakemake (default 1; with --profile as the profile says)")
    p_run.add_argument("--profile", help="a Snakemake profile folder, e.g. workflow/profiles/slurm")
    p_run.add_argument("--into", help="write studies/<study>/ under this folder (default: the current one)")
    p_table = sub.add_parser("table", help="print the table of a study's runs")
    p_table.add_argument("study", help="the study file or its folder studies/<study>")
    p_table.add_argument("--into", help="the folder that holds studies/ (default: the current one)")
    p_table.add_argument("--csv", action="store_true", help="print CSV instead of the aligned table")
    argv = list(sys.argv[1:] if argv is None else argv)
    extra = argv[argv.index("--") + 1:] if "--" in argv else []  # run ... -- SNAKEMAKE ARGS
    args = parser.parse_args(argv[:len(argv) - len(extra) - 1] if "--" in argv else argv)
    if extra and args.command != "run":
        parser.error("only run passes arguments after -- to Snakemake")
    try:
        if args.command == "run":
            run(args.study, cores=args.cores, profile=args.profile, into=args.into, extra=extra)
        else:
            from .study_table import Study

            table = Study(args.study, into=args.into).table()
            if args.csv:
                table.to_csv(sys.stdout, index=False)
            else:
                import pandas as pd

                with pd.option_context("display.max_rows", None, "display.max_columns", None, "display.width", 200):
                    print(table.to_string(index=False))
    except StudyError as e:
        print(f"granboltz.study: error: {e}", file=sys.stderr)
        return 2
    except subprocess.CalledProcessError as e:
        print(f"granboltz.study: error: Snakemake failed (status {e.returncode}); see its output above and the "
              "simulator's in studies/<study>/logs/", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
