#!/usr/bin/python3
"""Digest of an HDF5 output: one line per dataset, `path dtype shape sha256`, sorted by path.

Datasets only. Left out: everything under /provenance (host, times, command: differs between
identical runs) and every attribute. Attributes hold the stored config text (root `config`,
which grows when new config keys are emitted) and per-build values (`digest`, `git_sha`,
`version`); the numbers a run computes are in datasets. The hash is of the element bytes as
HDF5 returns them in the file's type, so chunking, compression and checksums do not enter.

Usage: digest.py FILE.h5 [-o OUT.txt]
"""
import argparse
import hashlib
import sys

import h5py
import numpy as np

EXCLUDED_PREFIXES = ("provenance",)
# The stored config, should a future version keep it as a dataset rather than an attribute.
EXCLUDED_NAMES = ("config",)


def excluded(path):
    first = path.split("/", 1)[0]
    return first in EXCLUDED_PREFIXES or path in EXCLUDED_NAMES


def dataset_bytes(ds):
    data = ds[()]
    if ds.dtype.kind == "O" or h5py.check_string_dtype(ds.dtype) is not None:
        # Variable-length data: hash each element's bytes with its length, in order.
        h = hashlib.sha256()
        for item in np.asarray(data, dtype=object).ravel():
            b = item if isinstance(item, bytes) else str(item).encode()
            h.update(len(b).to_bytes(8, "little"))
            h.update(b)
        return h.hexdigest()
    return hashlib.sha256(np.ascontiguousarray(np.asarray(data, dtype=ds.dtype)).tobytes()).hexdigest()


def digest(path):
    """The digest lines of the HDF5 file at `path`, sorted by dataset path."""
    lines = []
    with h5py.File(path, "r") as f:
        def visit(name, obj):
            if isinstance(obj, h5py.Dataset) and not excluded(name):
                shape = "[" + ",".join(str(s) for s in obj.shape) + "]"
                lines.append(f"/{name} {obj.dtype.str} {shape} {dataset_bytes(obj)}")
        f.visititems(visit)
    return sorted(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("file")
    ap.add_argument("-o", "--output", help="write here instead of stdout")
    a = ap.parse_args()
    text = "".join(line + "\n" for line in digest(a.file))
    if a.output:
        with open(a.output, "w") as out:
            out.write(text)
    else:
        sys.stdout.write(text)


if __name__ == "__main__":
    main()
