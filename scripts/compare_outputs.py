#!/usr/bin/python3
"""Checks that pairs of granboltz outputs are identical: every HDF5 dataset byte for byte and the
stored config (provenance such as host and wall time may differ); any other file byte for byte.

    compare_outputs.py A1 B1 [A2 B2 ...]     exit 0: all identical, 1: a difference (listed)
"""
import sys

import h5py
import numpy as np


def datasets(f):
    names = []
    f.visititems(lambda name, obj: names.append(name) if isinstance(obj, h5py.Dataset) else None)
    return sorted(names)


def differences(a, b):
    if not a.endswith(".h5"):
        with open(a, "rb") as fa, open(b, "rb") as fb:
            return [] if fa.read() == fb.read() else ["contents differ"]
    with h5py.File(a, "r") as fa, h5py.File(b, "r") as fb:
        if datasets(fa) != datasets(fb):
            return ["different datasets"]
        out = [n for n in datasets(fa) if np.asarray(fa[n][()]).tobytes() != np.asarray(fb[n][()]).tobytes()]
        if fa.attrs.get("config") != fb.attrs.get("config"):
            out.append("config attribute")
        return out


def main(paths):
    if len(paths) < 2 or len(paths) % 2:
        sys.exit("usage: compare_outputs.py A1 B1 [A2 B2 ...]")
    bad = 0
    for a, b in zip(paths[::2], paths[1::2]):
        diff = differences(a, b)
        print(f"{'identical' if not diff else 'DIFFERENT'}: {a} {b}" + (f" ({', '.join(diff)})" if diff else ""))
        bad += bool(diff)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
