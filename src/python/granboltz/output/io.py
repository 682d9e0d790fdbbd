"""Low-level reading of granboltz HDF5 outputs (docs/output.md, docs/tv06.md): opening a file,
reading one dataset with an error that names the file and the dataset, text attributes, and the
provenance of a run.

Every failure to read an output raises RunReadError naming the file and the dataset or attribute:
a path that is missing or a directory, a file that is not HDF5 or is truncated, a dataset HDF5
cannot read (for instance a Fletcher32 checksum failure of a corrupted file), a checkpoint, an
HDF5 file of another program, a config attribute that is not valid YAML. granboltz.output.run.read_run
adds the datasets and attributes every output of a model has, with their shapes and dtypes.
"""

import contextlib
import os

import h5py
import numpy as np
import yaml

MODELS = ("dsmc", "intruder", "needle")

# What h5py, NumPy and YAML raise on a damaged or hand-edited file: h5py gives OSError for most
# HDF5 errors, but KeyError, RuntimeError, ValueError or TypeError for some damaged objects.
_READ_ERRORS = (OSError, RuntimeError, KeyError, ValueError, TypeError, IndexError, OverflowError,
                yaml.YAMLError)


class RunReadError(OSError, ValueError):
    """A file that is not a complete granboltz output this package can read: names the file and
    the dataset (or attribute). An OSError (the file cannot be read) and a ValueError (its
    content is not what a granboltz output holds), so that callers catching either see it.

    path: the file; name: "the file", "dataset /time", "attribute config", ...; problem: what is
    wrong (text), and cause: the exception of h5py, NumPy or YAML behind it, if any."""

    def __init__(self, path, name, problem, message=None):
        self.path, self.name = str(path), name
        self.cause = problem if isinstance(problem, BaseException) else None
        self.problem = str(problem)
        if message is None:
            if self.cause is not None:
                message = f"{path}: cannot read {name}: {problem}"
            else:
                message = f"{path}: {problem}" if name == "the file" else f"{path}: {name}: {problem}"
        self._args = (self.path, name, problem, message)
        super().__init__(message)

    def __reduce__(self):
        # OSError would pickle only the message; keep the fields (multiprocessing, Snakemake).
        return type(self), self._args


@contextlib.contextmanager
def reading(path, name):
    """Turn any error of h5py, NumPy or YAML raised inside into RunReadError naming `name`."""
    try:
        yield
    except RunReadError:
        raise
    except _READ_ERRORS as err:
        raise RunReadError(path, name, err) from err


def _path(f, path):
    return f.filename if path is None else str(path)


def check_output(f, path=None):
    """Raise RunReadError unless the open file `f` looks like a granboltz output: a checkpoint
    (root attribute saved_utc, run.cpp write_checkpoint) and a file without the config
    attribute are refused with a message that says which it is."""
    path = _path(f, path)
    with reading(path, "the root attributes"):
        names = set(f.attrs)
        checkpoint = "saved_utc" in names or "in_progress" in f
    if checkpoint:
        raise RunReadError(path, "the file", "is a checkpoint",
                           message=f"{path}: is a checkpoint of an unfinished run, not an output; "
                                   "resume the run with granboltz run")
    if "config" not in names:
        raise RunReadError(path, "attribute config", "missing",
                           message=f"{path}: not a granboltz output (no /config attribute)")


@contextlib.contextmanager
def open_run(path):
    """Open a granboltz HDF5 output read-only. RunReadError for a missing path, a directory, a
    file HDF5 cannot open (not HDF5, truncated, damaged), a checkpoint and an HDF5 file without
    the config attribute."""
    path = os.fspath(path)
    if os.path.isdir(path):
        raise RunReadError(path, "the file", "is a directory, not an output file")
    if not os.path.exists(path):
        raise RunReadError(path, "the file", "no such file")
    try:
        f = h5py.File(path, "r")
    except _READ_ERRORS as err:
        raise RunReadError(path, "the file", err) from err
    with f:
        check_output(f, path)
        yield f


def text(value):
    """An HDF5 string attribute as str (h5py returns bytes or str depending on how it was written)."""
    return value.decode() if isinstance(value, bytes) else str(value)


def read_attribute(obj, key, path, where="", why=None):
    """The attribute `key` of the open group or dataset `obj`; RunReadError naming it if it is
    missing ("missing (why)") or HDF5 cannot read it. `where`: its owner, e.g. "/provenance"."""
    name = f"attribute {key}" + (f" of {where}" if where else "")
    with reading(path, name):
        if key not in obj.attrs:
            raise RunReadError(path, name, f"missing ({why})" if why else "missing")
        return obj.attrs[key]


def read_dataset(f, name, path=None):
    """The whole dataset `name` of the open file `f` as a NumPy array (or scalar). RunReadError
    naming the file and the dataset if it is missing, is a group, or HDF5 cannot read it (a
    checksum failure, a truncated file)."""
    path = _path(f, path)
    label = f"dataset /{name.lstrip('/')}"
    with reading(path, label):
        obj = f.get(name)
        if obj is None:
            raise RunReadError(path, label, "missing")
        if not isinstance(obj, h5py.Dataset):
            raise RunReadError(path, label, "is a group, not a dataset")
        return obj[()]


def check_finite(data, path, label):
    """RunReadError unless `data` is numeric and every value finite."""
    kind = np.asarray(data).dtype.kind
    if kind not in "fiub":
        raise RunReadError(path, label, f"is not numeric (dtype {np.asarray(data).dtype})")
    if kind == "f" and not np.all(np.isfinite(data)):
        raise RunReadError(path, label, "has non-finite values")


def read_finite(f, name, path=None):
    """read_dataset, refusing non-numeric and non-finite values (RunReadError naming the file and
    the dataset)."""
    path = _path(f, path)
    data = read_dataset(f, name, path)
    check_finite(data, path, f"dataset /{name.lstrip('/')}")
    return data


def _yaml_problem(err):
    return " ".join(str(err).split())


def read_config(f, path=None):
    """The resolved run config stored in the root attribute `config`, as a dict. RunReadError
    if it is missing, not text, not a YAML mapping, or has no known model."""
    path = _path(f, path)
    name = "attribute config"
    with reading(path, name):
        if "config" not in f.attrs:
            raise RunReadError(path, name, "missing",
                               message=f"{path}: not a granboltz output (no /config attribute)")
        raw = f.attrs["config"]
        if not isinstance(raw, (bytes, str)):
            raise RunReadError(path, name, f"is not text ({type(raw).__name__})")
        try:
            config = yaml.safe_load(text(raw))
        except yaml.YAMLError as err:
            raise RunReadError(path, name, f"is not valid YAML ({_yaml_problem(err)})") from err
    if not isinstance(config, dict):
        raise RunReadError(path, name, f"is not a YAML mapping ({type(config).__name__})")
    if "model" not in config:
        raise RunReadError(path, name, "has no model")
    if config["model"] not in MODELS:
        raise RunReadError(path, name, f"has an unknown model {config['model']!r} (expected {', '.join(MODELS)})")
    return config


def _number(value, kind, path, name):
    try:
        number = kind(_plain(value))
    except (TypeError, ValueError, OverflowError) as err:
        raise RunReadError(path, name, f"is not a number ({value!r})") from err
    if not np.isfinite(number):
        raise RunReadError(path, name, f"is not finite ({value!r})")
    return number


def run_attrs(f, path=None):
    """Provenance of an open output file: version, git_sha, wall_seconds (None if absent)."""
    path = _path(f, path)
    with reading(path, "the attributes of /provenance"):
        prov = f["provenance"].attrs if "provenance" in f else {}
        wall = prov.get("wall_seconds")
        version, sha = f.attrs.get("version", ""), f.attrs.get("git_sha", "")
        out = {"version": text(version), "git_sha": text(sha)}
    out["wall_seconds"] = (None if wall is None
                           else _number(wall, float, path, "attribute wall_seconds of /provenance"))
    return out


def _plain(value):
    """An attribute value as plain Python: text decoded, and numbers written as text parsed."""
    if isinstance(value, bytes):
        value = value.decode()
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, str):
        for kind in (int, float):
            try:
                return kind(value)
            except ValueError:
                pass
    return value


def provenance(f, path=None):
    """Every attribute of /provenance (run_config, command, threads, shard "i/count",
    wall_seconds, host, build, merged_from, ...) plus the root's version and git_sha, as plain
    Python values (numbers stored as text are parsed)."""
    path = _path(f, path)
    with reading(path, "the attributes of /provenance"):
        out = {"version": text(f.attrs.get("version", "")), "git_sha": text(f.attrs.get("git_sha", ""))}
        if "provenance" in f:
            out.update({key: _plain(value) for key, value in f["provenance"].attrs.items()})
    return out
