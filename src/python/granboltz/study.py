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

    from granboltz.study import Study, run     # Study: granboltz.study_table (also granboltz.Study)
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
import contextlib
import copy
import csv
import fcntl
import hashlib
import importlib
import io
import itertools
import json
import math
import os
import pathlib
import re
import shutil
import signal
import stat
import subprocess
import sys
import tempfile
import threading

import yaml

SNAKEFILE = pathlib.Path(__file__).resolve().with_name("study.smk")
_NAME = re.compile(r"[A-Za-z0-9_-]+")
_HASH = re.compile(r"[0-9a-f]{12}")
_PYTHON = "/usr/bin/python3"

# The limits of a study file: those of a config (docs/config.md), since its base is one, and a
# grid that cannot write a million files before anything asks.
MAX_POINTS = 10_000        # points of a grid; run(max_points=) and --max-points raise it
MAX_BYTES = 1 << 20        # a study file
MAX_NODES = 100_000        # YAML nodes, as written and again with every alias expanded
MAX_DEPTH = 64             # nested mappings and sequences, also through aliases
MAX_NAME = 100             # characters of a study name (a folder name)
_RUNTIME_KEYS = ("threads", "shard", "checkpoint")  # not in a run's stored config


class StudyError(ValueError):
    """A study file or folder that cannot be used, a simulator that cannot be found, or runs
    missing or damaged (table()). The message is one line."""


def _one_line(text, limit=80):
    """Free text on one line for a message: control and other unprintable characters escaped,
    cut at `limit` characters (saying how long it was)."""
    text = "".join(c if c.isprintable() else c.encode("unicode_escape").decode("ascii") for c in str(text))
    return text if len(text) <= limit else f"{text[:limit]}... ({len(text)} characters)"


def _show(value, limit=80):
    """A value on one line for a message: its repr, cut at `limit`."""
    return _one_line(repr(value), limit)


# ------------------------------------------------------------------------------ reading YAML
class _Limited(yaml.YAMLError):
    """A study file over a limit of _Loader (not a YAML syntax error)."""

    def __init__(self, problem, mark=None):
        super().__init__(problem)
        self.problem, self.problem_mark = problem, mark


class _Loader(yaml.SafeLoader):
    """PyYAML's safe loader with the config reader's limits: nodes as written and with every
    alias counted as the nodes it stands for (computed once per node, so an alias bomb is refused
    without being expanded), nesting depth (also through aliases), no alias inside the node it
    refers to, no key given twice."""

    def __init__(self, stream):
        super().__init__(stream)
        self._written = 0
        self._depth = 0
        self._sizes = {}  # id(node) -> (nodes with aliases expanded, levels), for finished nodes

    def compose_node(self, parent, index):
        event = self.peek_event()
        if isinstance(event, yaml.AliasEvent):
            target = self.anchors.get(event.anchor)
            if target is not None and id(target) not in self._sizes:
                raise _Limited(f"the alias *{_one_line(event.anchor, 40)} is inside the node it refers to",
                               event.start_mark)
            node = super().compose_node(parent, index)
            if self._depth + self._sizes[id(node)][1] > MAX_DEPTH:
                raise _Limited(f"nested more than {MAX_DEPTH} levels deep through the alias "
                               f"*{_one_line(event.anchor, 40)}", event.start_mark)
            self._count(event.start_mark)
            return node
        self._count(event.start_mark)
        collection = isinstance(event, (yaml.SequenceStartEvent, yaml.MappingStartEvent))
        if collection:
            self._depth += 1
            if self._depth > MAX_DEPTH:
                raise _Limited(f"nested more than {MAX_DEPTH} levels deep", event.start_mark)
        node = super().compose_node(parent, index)
        if collection:
            self._depth -= 1
            children = node.value if isinstance(node, yaml.SequenceNode) else \
                [n for pair in node.value for n in pair]
            sizes = [self._sizes[id(c)] for c in children]
            size = 1 + sum(s for s, _ in sizes)
            levels = 1 + max((h for _, h in sizes), default=0)
        else:
            size, levels = 1, 0
        if size > MAX_NODES:
            raise _Limited(f"more than {MAX_NODES} YAML nodes once its aliases are expanded "
                           "(an alias bomb?)", event.start_mark)
        self._sizes[id(node)] = (size, levels)
        return node

    def _count(self, mark):
        self._written += 1
        if self._written > MAX_NODES:
            raise _Limited(f"more than {MAX_NODES} YAML nodes", mark)

    def construct_mapping(self, node, deep=False):
        if isinstance(node, yaml.MappingNode):
            seen = set()
            for key_node, _ in node.value:
                if key_node.tag == "tag:yaml.org,2002:merge":
                    continue
                key = self.construct_object(key_node, deep=True)
                try:
                    new = key not in seen
                except TypeError:
                    continue  # unhashable: PyYAML says so itself
                if not new:
                    raise _Limited(f"the key {_show(key, 60)} is given twice", key_node.start_mark)
                seen.add(key)
        return super().construct_mapping(node, deep)


def _read_text(path, what, follow=True, limit=MAX_BYTES):
    """The text of the regular UTF-8 file `path` of at most `limit` bytes; StudyError otherwise.
    A FIFO or device is refused before it is read (opened without blocking); follow=False: a
    symbolic link is refused too."""
    flags = os.O_RDONLY | os.O_NONBLOCK | os.O_CLOEXEC | (0 if follow else os.O_NOFOLLOW)
    try:
        fd = os.open(path, flags)
    except OSError as e:
        if not follow and _lstat(path) is not None and stat.S_ISLNK(os.lstat(path).st_mode):
            raise StudyError(f"{path}: the {what} is a symbolic link, not a regular file") from None
        raise StudyError(f"{path}: cannot read the {what} ({e.strerror or e})") from None
    mode = os.fstat(fd).st_mode
    if not stat.S_ISREG(mode):
        os.close(fd)
        raise StudyError(f"{path}: the {what} is {_kind(mode)}, not a regular file")
    with os.fdopen(fd, "rb") as f:
        try:
            data = f.read(limit + 1)
        except OSError as e:
            raise StudyError(f"{path}: cannot read the {what} ({e.strerror or e})") from None
    if len(data) > limit:
        raise StudyError(f"{path}: the {what} has more than {limit} bytes (at most {limit})")
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as e:
        raise StudyError(f"{path}: the {what} is not UTF-8 text (byte 0x{data[e.start]:02x} at offset {e.start})") from None


def _kind(mode):
    for test, name in ((stat.S_ISLNK, "a symbolic link"), (stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a FIFO"),
                       (stat.S_ISSOCK, "a socket"), (stat.S_ISCHR, "a character device"),
                       (stat.S_ISBLK, "a block device")):
        if test(mode):
            return name
    return "not a regular file"


def load_yaml(text, path):
    """The YAML document `text` under the limits of a study file; StudyError naming `path`."""
    try:
        return yaml.load(text, Loader=_Loader)
    except _Limited as e:
        at = f" (line {e.problem_mark.line + 1})" if e.problem_mark is not None else ""
        raise StudyError(f"{path}: {e.problem}{at}") from None
    except yaml.YAMLError as e:
        where = getattr(e, "problem_mark", None)
        at = f" (line {where.line + 1})" if where is not None else ""
        problem = " ".join(str(getattr(e, "problem", None) or e).split())
        raise StudyError(f"{path}: not YAML{at}: {_one_line(problem, 200)}") from None
    except (ValueError, RecursionError) as e:  # an integer of more than 4300 digits, ...
        raise StudyError(f"{path}: not a usable YAML document ({_one_line(e, 120)})") from None


# ------------------------------------------------------------------------------ the study file
def load_study(path, max_points=MAX_POINTS, follow=True):
    """The study file at `path` checked (check_study): {"study": name, "base": dict, "grid":
    {key: [values]}}. max_points: the most points the grid may have (None: no limit);
    follow=False: a symbolic link is refused (a study folder's own study.yaml)."""
    path = pathlib.Path(path)
    spec = load_yaml(_read_text(path, "study file", follow=follow), path)
    return check_study(spec, path, max_points=max_points)


def _check_values(value, where, path, budget, depth=0):
    """StudyError unless `value` is plain data a config can hold: mappings with string keys,
    lists, strings, booleans, null, integers within 64 bits and finite floats. `budget`: [nodes
    left], so shared (aliased) parts cannot make the walk long."""
    budget[0] -= 1
    if budget[0] < 0:
        raise StudyError(f"{path}: more than {MAX_NODES} values in all (shared parts counted each time they are used)")
    if depth > MAX_DEPTH:
        raise StudyError(f"{path}: {_one_line(where, 100)}: nested more than {MAX_DEPTH} levels deep")
    if isinstance(value, dict):
        for key, item in value.items():
            if not isinstance(key, str) or not key:
                raise StudyError(f"{path}: {_one_line(where, 100)}: the key {_show(key, 40)} is not a non-empty string")
            _check_values(item, f"{where}.{key}", path, budget, depth + 1)
    elif isinstance(value, list):
        for i, item in enumerate(value):
            _check_values(item, f"{where}[{i}]", path, budget, depth + 1)
    elif isinstance(value, bool) or value is None:
        pass
    elif isinstance(value, int):
        if abs(value) >= 1 << 64:
            raise StudyError(f"{path}: {_one_line(where, 100)} = {_show(value, 40)}: an integer beyond 64 bits")
    elif isinstance(value, float):
        if not math.isfinite(value):
            raise StudyError(f"{path}: {_one_line(where, 100)} = {value}: a config value must be a finite number")
    elif isinstance(value, str):
        try:
            value.encode("utf-8")
        except UnicodeEncodeError:
            raise StudyError(f"{path}: {_one_line(where, 100)} = {_show(value)}: not a valid Unicode string") from None
    else:
        raise StudyError(f"{path}: {_one_line(where, 100)} = {_show(value)}: a {type(value).__name__} is not a config value "
                         "(numbers, strings, booleans, lists and mappings are)")


def check_study(spec, path="study", max_points=MAX_POINTS):
    """The study mapping checked (see load_study); StudyError with a one-line message otherwise."""
    if not isinstance(spec, dict):
        raise StudyError(f"{path}: a study file is a mapping with keys study, base and grid")
    unknown = sorted((k for k in spec if k not in ("study", "base", "grid")), key=repr)
    if unknown:
        raise StudyError(f"{path}: unknown key {_show(unknown[0], 60)} (allowed: study, base, grid)")
    name = spec.get("study")
    if not isinstance(name, str) or not _NAME.fullmatch(name):
        raise StudyError(f"{path}: study must be a name of letters, digits, _ and - (got {_show(name, 60)})")
    if len(name) > MAX_NAME:
        raise StudyError(f"{path}: study: a name of {len(name)} characters (at most {MAX_NAME})")
    base = spec.get("base")
    if not isinstance(base, dict) or not base:
        raise StudyError(f"{path}: base must be a config mapping (model, seed, ensembles, ...)")
    grid = spec.get("grid")
    if not isinstance(grid, dict) or not grid:
        raise StudyError(f"{path}: grid must be a non-empty mapping of dotted keys to lists of values")
    _check_values(base, "base", path, [MAX_NODES])
    budget = [MAX_NODES]
    for key, values in grid.items():
        if not isinstance(key, str) or not key or any(not part for part in key.split(".")):
            raise StudyError(f"{path}: grid key {_show(key, 60)} is not a dotted config key such as dsmc.alpha")
        if not isinstance(values, list) or not values:
            raise StudyError(f"{path}: grid.{_one_line(key, 60)} must be a non-empty list of values "
                             f"(got {_show(values, 60)})")
        _check_values(values, f"grid.{key}", path, budget)
        if len({canonical(v) for v in values}) != len(values):
            raise StudyError(f"{path}: grid.{_one_line(key, 60)} repeats a value")
        _set(copy.deepcopy(base), key, values[0], path)  # a key that cannot be set fails here
    count = math.prod(len(values) for values in grid.values())
    if max_points is not None and count > max_points:
        raise StudyError(f"{path}: the grid has {count} points, more than the limit {max_points} "
                         "(raise it with --max-points N, or run(..., max_points=N))")
    return {"study": name, "base": base, "grid": grid}


def _set(config, key, value, path="study"):
    """Set the dotted `key` of `config` to `value`, creating mappings on the way."""
    node, parts = config, key.split(".")
    for i, part in enumerate(parts[:-1]):
        child = node.setdefault(part, {})
        if not isinstance(child, dict):
            raise StudyError(f"{path}: grid key {_show(key, 60)}: {_one_line('.'.join(parts[:i + 1]), 60)} is not a mapping in base")
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


def point_text(config):
    """The text of a point file."""
    return yaml.safe_dump(config, sort_keys=True)


def _describe(values, limit=100):
    return _one_line(", ".join(f"{k}={_cell(v)}" for k, v in values.items()), limit)


def _parser():
    """The simulator's config parser: text, origin -> its normalized text, or ConfigError (a
    ValueError) with the simulator's one-line message. The extension granboltz._core where it
    is built, else `granboltz validate`."""
    try:
        core = importlib.import_module("granboltz._core")
        return core.normalized_config
    except ImportError:
        pass
    binary = find_binary()

    def validate(text, origin):
        with tempfile.TemporaryDirectory(prefix="granboltz-study-") as tmp:
            file = pathlib.Path(tmp, "point.yaml")
            file.write_text(text)
            out = subprocess.run([binary, "validate", str(file)], capture_output=True, text=True)
        if out.returncode != 0:
            line = (out.stderr.strip().splitlines() or ["refused"])[-1].removeprefix("granboltz: error: ")
            raise ValueError(line.replace(str(file), origin))
        return out.stdout
    return validate


def check_points(points, path="study"):
    """{hash: point file text} of expand()'s points, each config checked by the simulator's
    parser: StudyError naming the first point it refuses, with the simulator's message."""
    return {h: text for h, (text, _) in _check_points(points, path).items()}


def _check_points(points, path):
    """check_points, with each point's run config: {hash: (point text, run_config)}."""
    parse = _parser()
    checked = {}
    for h, values, config in points:
        text = point_text(config)
        try:
            checked[h] = (text, run_config(parse(text, f"point {h}")))
        except (ValueError, RuntimeError, TypeError) as e:
            message = " ".join(str(e).split())
            raise StudyError(f"{path}: point {h} ({_describe(values)}): {_one_line(message, 400)}") from None
    return checked


def run_config(normalized):
    """The config a run of a point stores, from the point's config as the simulator's parser
    prints it (every default explicit, keys its settings ignore left out): without threads,
    shard and checkpoint, which a run does not store."""
    config = yaml.safe_load(normalized)
    if not isinstance(config, dict):
        raise ValueError(f"the simulator's parser printed no config mapping ({_one_line(normalized, 60)})")
    for key in _RUNTIME_KEYS:
        config.pop(key, None)
    return config


# ------------------------------------------------------------------------------ the folder
def _lstat(path):
    try:
        return os.lstat(path)
    except FileNotFoundError:
        return None
    except OSError as e:
        raise StudyError(f"{path}: cannot look at it ({e.strerror or e})") from None


_PARTS = ("points", "runs", "logs", "damaged", ".snakemake")


def check_folder(folder):
    """StudyError unless the study folder (if it exists) is a folder whose parts (points/, runs/,
    logs/, damaged/, .snakemake/ and everything in .snakemake/) are its own: folders and files,
    never a symbolic link, so nothing written in it lands elsewhere."""
    st = _lstat(folder)
    if st is None:
        return
    try:
        st = os.stat(folder)  # the study folder itself may be a link (to a scratch disk, say)
    except OSError as e:
        raise StudyError(f"{folder}: the study folder cannot be used ({e.strerror or e})") from None
    if not stat.S_ISDIR(st.st_mode):
        raise StudyError(f"{folder}: the study folder is {_kind(st.st_mode)}, not a folder")
    for part in _PARTS:
        st = _lstat(folder / part)
        if st is not None and not stat.S_ISDIR(st.st_mode):
            raise StudyError(f"{folder / part}: is {_kind(st.st_mode)}, not a folder of the study "
                             "(move it away; the study makes its own)")
    for root, dirs, files in os.walk(folder / ".snakemake"):
        for name in dirs + files:
            st = _lstat(os.path.join(root, name))
            if st is not None and not (stat.S_ISDIR(st.st_mode) or stat.S_ISREG(st.st_mode)):
                raise StudyError(f"{os.path.join(root, name)}: is {_kind(st.st_mode)} inside Snakemake's folder "
                                 "(move it away)")


def _move_aside(path, folder):
    """Move `path` (a file, folder, link or FIFO of the study folder, never followed) into
    damaged/ under a fresh name; returns the new path."""
    aside = folder / "damaged"
    aside.mkdir(exist_ok=True)
    stem = str(path.relative_to(folder)).replace(os.sep, "-")
    for n in itertools.count():
        target = aside / (stem if n == 0 else f"{stem}.{n}")
        if _lstat(target) is None:
            break
    try:
        os.rename(path, target)
    except OSError as e:
        raise StudyError(f"{path}: cannot move it aside to {target} ({e.strerror or e})") from None
    return target


def _write_if_changed(path, text, folder=None):
    """Write `text` to `path` (atomically) only when the file does not already hold it. Whatever
    is at `path` and is not a regular file (a link, folder, FIFO) is moved to damaged/ first."""
    path = pathlib.Path(path)
    folder = pathlib.Path(folder) if folder is not None else path.parent
    data = text.encode()
    st = _lstat(path)
    if st is not None and stat.S_ISREG(st.st_mode):
        try:
            fd = os.open(path, os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK | os.O_CLOEXEC)
            with os.fdopen(fd, "rb") as f:
                if f.read(len(data) + 1) == data:
                    return False
        except OSError:
            pass
    elif st is not None:
        _move_aside(path, folder)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise
    return True


def _cell(value):
    return value if isinstance(value, str) else canonical(value)


def study_folder(spec, into=None):
    """The folder of a checked study: studies/<study> under `into` (default the current directory)."""
    return pathlib.Path(into or ".").absolute() / "studies" / spec["study"]


def _plan(study_file, into, max_points):
    """Everything checked, nothing written: (spec, folder, points, {hash: point text})."""
    spec = load_study(study_file, max_points)
    folder = study_folder(spec, into)
    points = expand(spec)
    checked = _check_points(points, study_file)
    check_folder(folder)
    return spec, folder, points, checked


def _write_folder(spec, folder, points, checked):
    for h, _, _ in points:
        _write_if_changed(folder / "points" / f"{h}.yaml", checked[h][0], folder)
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(["hash", *spec["grid"]])
    for h, values, _ in points:
        writer.writerow([h, *(_cell(values[k]) for k in spec["grid"])])
    _write_if_changed(folder / "index.csv", out.getvalue(), folder)
    _write_if_changed(folder / "study.yaml", yaml.safe_dump(spec, sort_keys=False), folder)


def prepare(study_file, into=None, max_points=MAX_POINTS):
    """Expand the study file, check every point, and write its folder (study.yaml, points/,
    index.csv); returns (folder, points) with points as expand() gives them."""
    spec, folder, points, checked = _plan(study_file, into, max_points)
    with _runner_lock(folder):
        _write_folder(spec, folder, points, checked)
    return folder, points


# ------------------------------------------------------------------------------ runs
def run_difference(config, stored, where=""):
    """None when every value of the point `config` is the stored (resolved) config's value at
    that key, else the first key that differs (the simulator adds defaults; threads, shard and
    checkpoint are not stored)."""
    if isinstance(config, dict):
        if not isinstance(stored, dict):
            return where or "the config"
        for key, value in config.items():
            if not where and key in _RUNTIME_KEYS:
                continue
            if key not in stored:
                return f"{where}{key}"
            found = run_difference(value, stored[key], f"{where}{key}.")
            if found:
                return found
        return None
    if isinstance(config, list):
        if not isinstance(stored, list) or len(stored) != len(config):
            return where.rstrip(".")
        for i, (a, b) in enumerate(zip(config, stored)):
            if run_difference(a, b, f"{where.rstrip('.')}[{i}]."):
                return f"{where.rstrip('.')}[{i}]"
        return None
    if isinstance(config, bool) != isinstance(stored, bool) or config != stored:
        return where.rstrip(".")
    return None


def _shard(config):
    shard = config.get("shard") if isinstance(config, dict) else None
    if isinstance(shard, dict) and isinstance(shard.get("count"), int) and shard["count"] > 1:
        return shard.get("index", 0), shard["count"]
    return None


def identity_problem(config, stored, shard, expected=None):
    """None when a run whose stored config is `stored` and whose shard is `shard` ((index,
    count) or None) is the run of the point `config`, else what is wrong, briefly. expected:
    the point's run_config (the simulator's parser's resolution of it): every value the run
    stores must be its value there (a run of an older simulator may lack keys added since);
    None (no parser at hand): every value of the point's own config must be stored."""
    where = run_difference(stored, expected) if expected is not None else run_difference(config, stored)
    if where:
        return f"the run of another point (its {_one_line(where, 60)} differs)"
    if shard != _shard(config):
        return f"a shard {shard[0]}/{shard[1]}, not the whole run" if shard else "not the shard of this point"
    return None


def _file_shard(f):
    prov = f["provenance"].attrs if "provenance" in f else {}
    if "merged_from" in prov:
        return None
    raw = prov.get("shard", b"")
    index, _, count = (raw.decode() if isinstance(raw, bytes) else str(raw)).partition("/")
    return (int(index), int(count)) if index.isdigit() and count.isdigit() and int(count) > 1 else None


def stored_identity_problem(path, config, expected=None):
    """None when the output at `path` (a regular file that `granboltz verify` passed) is the run
    of the point `config` (expected: its run_config), else a short reason: read its stored
    config and shard only."""
    from .io import RunReadError, open_run, read_config

    try:
        with open_run(path) as f:
            stored = read_config(f, path)
            shard = _file_shard(f)
    except (RunReadError, OSError, ValueError, KeyError) as e:
        return f"damaged: {_brief(e, path)}"
    return identity_problem(config, stored, shard, expected)


def _brief(error, path):
    text = " ".join(str(error).split()).replace(f"{path}: ", "").replace(str(path), "the file")
    return _one_line(text, 100)


def not_regular(path):
    """None for a regular file (not followed), "missing", or what is there instead."""
    st = _lstat(path)
    if st is None:
        return "missing"
    return None if stat.S_ISREG(st.st_mode) else f"{_kind(st.st_mode)}, not a regular file"


def verify_runs(folder, hashes, binary):
    """{hash: problem} for the runs/<hash>.h5 (regular files) that `granboltz verify` does not pass."""
    problems = {}
    names = [f"{h}.h5" for h in hashes]
    line = re.compile(r"granboltz: error: ([0-9a-f]{12})\.h5: (?:damaged: )?(.*)")
    for start in range(0, len(names), 500):
        batch = names[start:start + 500]
        try:
            out = subprocess.run([binary, "verify", *batch], cwd=folder / "runs", capture_output=True, text=True,
                                 errors="replace")
        except OSError as e:
            raise StudyError(f"{binary}: cannot run granboltz verify ({e.strerror or e})") from None
        ok = {ln.split(":", 1)[0][:-3] for ln in out.stdout.splitlines() if re.fullmatch(r"[0-9a-f]{12}\.h5: ok.*", ln)}
        said = {m.group(1): m.group(2) for m in map(line.fullmatch, out.stderr.splitlines()) if m}
        for name in batch:
            h = name[:-3]
            if h not in ok:
                problems[h] = "damaged: " + _one_line(said.get(h, f"granboltz verify exited {out.returncode}"), 100)
    return problems


def check_runs(folder, points, binary, expected=None):
    """{hash: problem} of the points whose run is missing, not a regular file, damaged (granboltz
    verify) or of another point (its stored config; expected: {hash: run_config})."""
    problems, present = {}, []
    for h, _, _ in points:
        problem = not_regular(folder / "runs" / f"{h}.h5")
        if problem:
            problems[h] = problem
        else:
            present.append(h)
    if present:
        problems.update(verify_runs(folder, present, binary))
    configs = {h: config for h, _, config in points}
    for h in present:
        if h not in problems:
            problem = stored_identity_problem(folder / "runs" / f"{h}.h5", configs[h], (expected or {}).get(h))
            if problem:
                problems[h] = problem
    return problems


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


# ------------------------------------------------------------------------------ one runner at a time
LOCK_NAME = ".runner.lock"


@contextlib.contextmanager
def _runner_lock(folder):
    """Hold the study folder's runner lock (flock on .runner.lock, which also holds the runner's
    pid); yields the lock's file descriptor, to be inherited by Snakemake so that the lock lives
    as long as the runner or its Snakemake does, or None where the file system has no flock.
    StudyError when another runner holds it."""
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / LOCK_NAME
    st = _lstat(path)
    if st is not None and not stat.S_ISREG(st.st_mode):
        _move_aside(path, folder)
    try:
        fd = os.open(path, os.O_RDWR | os.O_CREAT | os.O_NOFOLLOW | os.O_NONBLOCK | os.O_CLOEXEC, 0o644)
    except OSError as e:
        raise StudyError(f"{path}: cannot open the runner lock ({e.strerror or e})") from None
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            held = True
        except BlockingIOError:
            pid = os.pread(fd, 40, 0).decode(errors="replace").split()
            raise StudyError(f"{folder}: another `granboltz.study run` of this study, or the Snakemake it "
                             f"started, is running{' (runner pid ' + pid[0] + ')' if pid and pid[0].isdigit() else ''}; "
                             "wait for it or stop it (SIGTERM)") from None
        except OSError:  # no flock here (some network file systems): no stale-lock recovery either
            held = False
        if held:
            os.ftruncate(fd, 0)
            os.pwrite(fd, f"{os.getpid()}\n".encode(), 0)
        yield fd if held else None
    finally:
        os.close(fd)


def _unlock_stale(folder, binary, quiet):
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
                         f"{out.returncode}: {_one_line((out.stderr.strip().splitlines() or [''])[-1], 120)})")
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


class _Stopped(Exception):
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


def run(study_file, cores=None, profile=None, into=None, quiet=False, extra=(), max_points=MAX_POINTS):
    """Write the study folder and run the points without a sound run of their own (Snakemake, with
    `cores` local cores, default 1, or through the Snakemake `profile` folder, e.g.
    workflow/profiles/slurm). Runs that are damaged, of another point or not regular files are
    moved to damaged/ and made again. max_points: the most points the grid may have (None: no
    limit). Returns the Study. Raises StudyError for a bad study file or folder, no simulator or
    another runner of the study alive (before anything is written), subprocess.CalledProcessError
    when Snakemake fails. SIGTERM and SIGINT stop Snakemake and the simulator first (run_snakemake)."""
    from .study_table import Study

    if max_points is not None and (isinstance(max_points, bool) or not isinstance(max_points, int) or max_points < 1):
        raise StudyError(f"max_points = {_show(max_points, 40)}: must be an integer >= 1 (or None: no limit)")
    spec, folder, points, checked = _plan(study_file, into, max_points)
    binary = find_binary()
    say = (lambda msg: None) if quiet else (lambda msg: print(f"granboltz.study: {msg}", flush=True))
    with _runner_lock(folder) as lock_fd:
        if lock_fd is not None:
            _unlock_stale(folder, binary, quiet)
        _write_folder(spec, folder, points, checked)
        problems = check_runs(folder, points, binary, {h: c for h, (_, c) in checked.items()})
        for h, problem in problems.items():
            for path in (folder / "runs" / f"{h}.h5", folder / "logs" / f"{h}.log"):
                st = _lstat(path)
                if st is not None and (path.suffix == ".h5" or not stat.S_ISREG(st.st_mode)):
                    moved = _move_aside(path, folder)
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
    argv = list(sys.argv[1:] if argv is None else argv)
    extra = argv[argv.index("--") + 1:] if "--" in argv else []  # run ... -- SNAKEMAKE ARGS
    args = parser.parse_args(argv[:len(argv) - len(extra) - 1] if "--" in argv else argv)
    if extra and args.command != "run":
        parser.error("only run passes arguments after -- to Snakemake")
    if args.command == "run" and args.max_points < 1:
        parser.error(f"argument --max-points: must be >= 1 (got {args.max_points})")

    def stopped(signum, frame):
        raise _Stopped

    previous = signal.signal(signal.SIGTERM, stopped) if signal.getsignal(signal.SIGTERM) == signal.SIG_DFL else None
    try:
        if args.command == "run":
            run(args.study, cores=args.cores, profile=args.profile, into=args.into, extra=extra,
                max_points=args.max_points)
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
    except (_Stopped, KeyboardInterrupt) as e:
        name = "SIGTERM" if isinstance(e, _Stopped) else "SIGINT"
        print(f"granboltz.study: stopped by {name} (Snakemake and the simulator too); run again to resume",
              file=sys.stderr)
        return 128 + (signal.SIGTERM if isinstance(e, _Stopped) else signal.SIGINT)
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)
    return 0


if __name__ == "__main__":
    # Run as `python -m granboltz.study`, this file is the module __main__, whose StudyError is
    # another class than granboltz.study.StudyError (which study_table raises): run the
    # package's module instead, so that every error is caught as the one class.
    from granboltz.study import main as _main

    sys.exit(_main())
