"""The manifest of a DSMC output: /manifest lists every dataset the run presents, with its shape,
its meaning and the observer that wrote it (src/granboltz/dsmc/observers/presenter.cpp,
docs/output.md). granboltz.output.run.read_run checks an output against it: every listed dataset
present with the listed shape; a damaged manifest or a missing or misshapen dataset raises
RunReadError naming the file and the object. Outputs written before the manifest existed have no
/manifest: read_manifest returns None and the reader relies on the layout it derives from the
config (granboltz.output.layout), as it always has.

    run = read_run("out.h5")
    run.manifest["/temperature/mean"].shape      # (M + 1,)
    run.manifest["/temperature/mean"].meaning    # text
    run.manifest["/temperature/mean"].observer   # "moments"
"""

from dataclasses import dataclass

import h5py

from .io import reading

_COLUMNS = ("path", "observer", "meaning", "rank", "shape")


@dataclass(frozen=True)
class ManifestEntry:
    """One dataset of an output's manifest: its absolute path, shape (a tuple; () for a scalar),
    meaning (text) and the observer that wrote it."""

    path: str
    shape: tuple
    meaning: str
    observer: str


def _column(reader, name, rows=None):
    """/manifest/<name> as a NumPy array, checked to be a dataset with `rows` rows (1-D text, or
    unsigned integers: rank 1-D, shape 2-D)."""
    label = f"dataset /manifest/{name}"
    with reading(reader.path, label):
        obj = reader.f.get(f"manifest/{name}")
        if not isinstance(obj, h5py.Dataset):
            reader.fail(label, "missing (every output with a /manifest has it)" if obj is None
                        else "is a group, not a dataset")
        text = name in ("path", "observer", "meaning")
        ndim = 2 if name == "shape" else 1
        kind_ok = obj.dtype.kind == "S" if text else obj.dtype.kind == "u"
        if not kind_ok or len(obj.shape) != ndim:
            reader.fail(label, f"has dtype {obj.dtype} and shape {obj.shape}, not "
                               f"{'text' if text else 'unsigned integers'} of {ndim} dimension(s)")
        if rows is not None and obj.shape[0] != rows:
            reader.fail(label, f"has {obj.shape[0]} rows, but /manifest/path has {rows}")
        data = obj[()]
        if text:
            data = [value.decode("utf-8") for value in data]
    return data


def read_manifest(reader):
    """{path: ManifestEntry} of the output's /manifest in the order written, after checking that
    every listed dataset is present with the listed shape; None if the file has no /manifest
    (written before it existed). RunReadError, naming the file and the object, for a damaged
    manifest or a listed dataset that is missing or has another shape."""
    if not reader.exists("manifest"):
        return None
    reader.group("manifest", "")
    paths = _column(reader, "path")
    rows = len(paths)
    observers, meanings = _column(reader, "observer", rows), _column(reader, "meaning", rows)
    rank, shape = _column(reader, "rank", rows), _column(reader, "shape", rows)
    out = {}
    for k, path in enumerate(paths):
        if not path.startswith("/") or path in out:
            reader.fail("dataset /manifest/path",
                        f"row {k} is {path!r}, not an absolute path listed once")
        if rank[k] > shape.shape[1]:
            reader.fail("dataset /manifest/rank",
                        f"row {k} is {rank[k]}, more than the {shape.shape[1]} columns of /manifest/shape")
        listed = tuple(int(n) for n in shape[k, :rank[k]])
        label = f"dataset {path}"
        with reading(reader.path, label):
            obj = reader.f.get(path[1:])
            if not isinstance(obj, h5py.Dataset):
                reader.fail(label, "missing (listed in /manifest)" if obj is None
                            else "is a group, but /manifest lists a dataset")
            if obj.shape != listed:
                reader.fail(label, f"has shape {obj.shape}, but /manifest lists {listed}")
        out[path] = ManifestEntry(path=path, shape=listed, meaning=meanings[k], observer=observers[k])
    return out

