"""The study file of a parameter study (granboltz.study) and its points: the file checked
(load_study, check_study: names, keys, values a config can hold, at most MAX_POINTS points),
expanded into points named by the hash of their config (expand, point_hash), and every point's
config checked by the simulator's own parser (check_points) before anything is written."""

import copy
import hashlib
import importlib
import itertools
import json
import math
import os
import pathlib
import re
import shutil
import subprocess
import tempfile

import yaml

from .grid import check_replicas, full_grid, set_key
from .safe_yaml import MAX_DEPTH, MAX_NODES, StudyError, one_line, read_text, show, load_yaml

_NAME = re.compile(r"[A-Za-z0-9_-]+")
_HASH = re.compile(r"[0-9a-f]{12}")
MAX_POINTS = 10_000        # points of a grid; run(max_points=) and --max-points raise it
MAX_NAME = 100             # characters of a study name (a folder name)
RUNTIME_KEYS = ("threads", "shard", "checkpoint")  # not in a run's stored config


def load_study(path, max_points=MAX_POINTS, follow=True):
    """The study file at `path` checked (check_study): {"study": name, "base": dict, "grid":
    {key: [values]}}. max_points: the most points the grid may have (None: no limit);
    follow=False: a symbolic link is refused (a study folder's own study.yaml)."""
    path = pathlib.Path(path)
    spec = load_yaml(read_text(path, "study file", follow=follow), path)
    return check_study(spec, path, max_points=max_points)


def _check_values(value, where, path, budget, depth=0):
    """StudyError unless `value` is plain data a config can hold: mappings with string keys,
    lists, strings, booleans, null, integers within 64 bits and finite floats. `budget`: [nodes
    left], so shared (aliased) parts cannot make the walk long."""
    budget[0] -= 1
    if budget[0] < 0:
        raise StudyError(f"{path}: more than {MAX_NODES} values in all (shared parts counted each time they are used)")
    if depth > MAX_DEPTH:
        raise StudyError(f"{path}: {one_line(where, 100)}: nested more than {MAX_DEPTH} levels deep")
    if isinstance(value, dict):
        for key, item in value.items():
            if not isinstance(key, str) or not key:
                raise StudyError(f"{path}: {one_line(where, 100)}: the key {show(key, 40)} is not a non-empty string")
            _check_values(item, f"{where}.{key}", path, budget, depth + 1)
    elif isinstance(value, list):
        for i, item in enumerate(value):
            _check_values(item, f"{where}[{i}]", path, budget, depth + 1)
    elif isinstance(value, bool) or value is None:
        pass
    elif isinstance(value, int):
        if abs(value) >= 1 << 64:
            raise StudyError(f"{path}: {one_line(where, 100)} = {show(value, 40)}: an integer beyond 64 bits")
    elif isinstance(value, float):
        if not math.isfinite(value):
            raise StudyError(f"{path}: {one_line(where, 100)} = {value}: a config value must be a finite number")
    elif isinstance(value, str):
        try:
            value.encode("utf-8")
        except UnicodeEncodeError:
            raise StudyError(f"{path}: {one_line(where, 100)} = {show(value)}: not a valid Unicode string") from None
    else:
        raise StudyError(f"{path}: {one_line(where, 100)} = {show(value)}: a {type(value).__name__} is not a config value "
                         "(numbers, strings, booleans, lists and mappings are)")


def check_study(spec, path="study", max_points=MAX_POINTS):
    """The study mapping checked (see load_study); StudyError with a one-line message otherwise."""
    if not isinstance(spec, dict):
        raise StudyError(f"{path}: a study file is a mapping with keys study, base and grid")
    unknown = sorted((k for k in spec if k not in ("study", "base", "grid", "replicas")), key=repr)
    if unknown:
        raise StudyError(f"{path}: unknown key {show(unknown[0], 60)} (allowed: study, base, grid, replicas)")
    name = spec.get("study")
    if not isinstance(name, str) or not _NAME.fullmatch(name):
        raise StudyError(f"{path}: study must be a name of letters, digits, _ and - (got {show(name, 60)})")
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
            raise StudyError(f"{path}: grid key {show(key, 60)} is not a dotted config key such as dsmc.alpha")
        if not isinstance(values, list) or not values:
            raise StudyError(f"{path}: grid.{one_line(key, 60)} must be a non-empty list of values "
                             f"(got {show(values, 60)})")
        _check_values(values, f"grid.{key}", path, budget)
        if len({canonical(v) for v in values}) != len(values):
            raise StudyError(f"{path}: grid.{one_line(key, 60)} repeats a value")
        set_key(copy.deepcopy(base), key, values[0], path)  # a key that cannot be set fails here
    replicas = check_replicas(spec, base, grid, path)
    count = math.prod(len(values) for values in grid.values()) * (len(replicas) if replicas else 1)
    if max_points is not None and count > max_points:
        raise StudyError(f"{path}: the grid has {count} points, more than the limit {max_points} "
                         "(raise it with --max-points N, or run(..., max_points=N))")
    out = {"study": name, "base": base, "grid": grid}
    if "replicas" in spec:
        out["replicas"] = spec["replicas"]
    return out


def canonical(value):
    """The canonical JSON of a config (sorted keys, no spaces): what the point hash is taken of."""
    return json.dumps(value, sort_keys=True, separators=(",", ":"), ensure_ascii=False, allow_nan=False)


def point_hash(config):
    """The first 12 hex digits of the sha256 of the config's canonical JSON."""
    return hashlib.sha256(canonical(config).encode()).hexdigest()[:12]


def expand(spec):
    """The points of a checked study: [(hash, {grid key: value}, config)] in grid order (the
    last key varies fastest)."""
    grid = full_grid(spec)
    keys = list(grid)
    points, seen = [], set()
    for values in itertools.product(*(grid[k] for k in keys)):
        config = copy.deepcopy(spec["base"])
        for key, value in zip(keys, values):
            set_key(config, key, value)
        h = point_hash(config)
        if h not in seen:  # two grid values that give one config (e.g. 1 and 1.0 never do: JSON keeps them apart)
            seen.add(h)
            points.append((h, dict(zip(keys, values)), config))
    return points


def point_text(config):
    """The text of a point file."""
    return yaml.safe_dump(config, sort_keys=True)


def cell_text(value):
    """A table cell: strings as they are, other values in their canonical text."""
    return value if isinstance(value, str) else canonical(value)


def _describe(values, limit=100):
    return one_line(", ".join(f"{k}={cell_text(v)}" for k, v in values.items()), limit)


def study_folder(spec, into=None):
    """The folder of a checked study: studies/<study> under `into` (default the current directory)."""
    return pathlib.Path(into or ".").absolute() / "studies" / spec["study"]


def find_binary():
    """The granboltz simulator: $GRANBOLTZ_BIN, else the one installed with this package (pip
    install .), else build/granboltz of this source tree, else `granboltz` on PATH (absolute
    path); StudyError if none is executable."""
    from ..lib.cli import simulator

    env = os.environ.get("GRANBOLTZ_BIN")
    if env:
        if os.access(env, os.X_OK) and os.path.isfile(env):
            return str(pathlib.Path(env).absolute())
        raise StudyError(f"GRANBOLTZ_BIN={env} is not an executable file")
    own = simulator()
    if own:
        return own
    tree = pathlib.Path(__file__).resolve().parents[4] / "build" / "granboltz"
    found = shutil.which("granboltz")
    if found:
        return str(pathlib.Path(found).absolute())
    raise StudyError(f"no granboltz simulator: set GRANBOLTZ_BIN, build {tree} (make build) or put granboltz on PATH")


def study_parser():
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
    return {h: text for h, (text, _) in check_point_list(points, path).items()}


def check_point_list(points, path):
    """check_points, with each point's run config: {hash: (point text, run_config)}."""
    parse = study_parser()
    checked = {}
    for h, values, config in points:
        text = point_text(config)
        try:
            checked[h] = (text, run_config(parse(text, f"point {h}")))
        except (ValueError, RuntimeError, TypeError) as e:
            message = " ".join(str(e).split())
            raise StudyError(f"{path}: point {h} ({_describe(values)}): {one_line(message, 400)}") from None
    return checked


def run_config(normalized):
    """The config a run of a point stores, from the point's config as the simulator's parser
    prints it (every default explicit, keys its settings ignore left out): without threads,
    shard and checkpoint, which a run does not store."""
    config = yaml.load(normalized, Loader=getattr(yaml, "CSafeLoader", yaml.SafeLoader))  # the simulator's own text
    if not isinstance(config, dict):
        raise ValueError(f"the simulator's parser printed no config mapping ({one_line(normalized, 60)})")
    for key in RUNTIME_KEYS:
        config.pop(key, None)
    return config
