"""Writing the workflow's outputs atomically (CSV, text, JSON) and reading CSV tables back.

A failed step leaves no half-written output: every writer goes through atomic_path.
"""

import contextlib
import csv
import json
import math
import os
import tempfile

import numpy as np


@contextlib.contextmanager
def atomic_path(path):
    """Yield a temporary name in the directory of `path`; rename it to `path` on success.

    A failed step leaves no half-written output: the temporary file is removed instead.
    """
    directory = os.path.dirname(os.path.abspath(path))
    os.makedirs(directory, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=directory, prefix="." + os.path.basename(path) + ".", suffix=".tmp")
    os.close(fd)
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o666 & ~umask)
    try:
        yield tmp
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.remove(tmp)
        raise


def write_csv(rows, columns, path, digits=4):
    """Write dict rows as CSV (floats with `digits` significant digits, None as empty), atomically."""

    def cell(value):
        if value is None:
            return ""
        if isinstance(value, (float, np.floating)):
            return f"{value:.{digits}g}" if math.isfinite(value) else "nan"
        return str(value)

    with atomic_path(path) as tmp:
        with open(tmp, "w", newline="") as out:
            writer = csv.writer(out, lineterminator="\n")
            writer.writerow(columns)
            for row in rows:
                writer.writerow([cell(row[c]) for c in columns])


def write_text(text, path):
    """Write a text file atomically."""
    with atomic_path(path) as tmp:
        with open(tmp, "w") as out:
            out.write(text)


def write_json(obj, path):
    """Write a JSON file (sorted keys, floats as they are), atomically."""
    write_text(json.dumps(obj, indent=1, sort_keys=True, default=float) + "\n", path)


def read_csv(path):
    """Rows of a CSV file as dicts of strings."""
    with open(path, newline="") as f:
        return list(csv.DictReader(f))

