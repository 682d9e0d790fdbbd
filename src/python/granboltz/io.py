"""Low-level reading of granboltz HDF5 outputs (docs/output.md, docs/tv06.md): opening a file,
reading one dataset with an error that names the file and the dataset, text attributes, and the
provenance of a run.

Every reader of the package goes through read_dataset, so a dataset that HDF5 cannot read (for
instance a Fletcher32 checksum failure of a corrupted file) surfaces as RunReadError naming both
the file and the dataset instead of h5py's bare message.
"""

import contextlib

import h5py
import numpy as np
import yaml


class RunReadError(OSError):
    """A granboltz output that cannot be read: names the file and the dataset (or attribute)."""

    def __init__(self, path, name, cause):
        self.path, self.name, self.cause = str(path), name, cause
        super().__init__(f"{path}: cannot read {name}: {cause}")


@contextlib.contextmanager
def open_run(path):
    """Open a granboltz HDF5 output read-only; a file HDF5 cannot open raises RunReadError."""
    try:
        f = h5py.File(path, "r")
    except OSError as err:
        raise RunReadError(path, "the file", err) from err
    with f:
        yield f


def text(value):
    """An HDF5 string attribute as str (h5py returns bytes or str depending on how it was written)."""
    return value.decode() if isinstance(value, bytes) else str(value)


def read_dataset(f, name, path=None):
    """The whole dataset `name` of the open file `f` as a NumPy array (or scalar); any error of
    HDF5 while reading it (a checksum failure, a truncated file) raises RunReadError naming the
    file and the dataset."""
    path = f.filename if path is None else path
    try:
        return f[name][()]
    except KeyError:
        raise
    except (OSError, RuntimeError, ValueError) as err:
        raise RunReadError(path, f"dataset /{name}", err) from err


def read_finite(f, name, path=None):
    """read_dataset, refusing non-finite values (ValueError naming the file and the dataset)."""
    path = f.filename if path is None else path
    data = read_dataset(f, name, path)
    if not np.all(np.isfinite(data)):
        raise ValueError(f"{path}: dataset /{name} has non-finite values")
    return data


def read_config(f, path=None):
    """The resolved run config stored in the root attribute `config`, as a dict."""
    path = f.filename if path is None else path
    try:
        return yaml.safe_load(text(f.attrs["config"]))
    except KeyError:
        raise RunReadError(path, "attribute config", "missing (not a granboltz output?)") from None


def run_attrs(f):
    """Provenance of an open output file: version, git_sha, wall_seconds (None if absent)."""
    prov = f["provenance"].attrs if "provenance" in f else {}
    wall = prov.get("wall_seconds")
    return {
        "version": text(f.attrs.get("version", "")),
        "git_sha": text(f.attrs.get("git_sha", "")),
        "wall_seconds": None if wall is None else float(wall),
    }


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


def provenance(f):
    """Every attribute of /provenance (run_config, command, threads, shard "i/count",
    wall_seconds, host, build, merged_from, ...) plus the root's version and git_sha, as plain
    Python values (numbers stored as text are parsed)."""
    out = {"version": text(f.attrs.get("version", "")), "git_sha": text(f.attrs.get("git_sha", ""))}
    if "provenance" in f:
        out.update({key: _plain(value) for key, value in f["provenance"].attrs.items()})
    return out
