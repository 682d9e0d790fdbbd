"""The `granboltz` command that `pip install .` puts into an environment: the simulator
installed with the package (granboltz/_bin/granboltz), else, for an editable install,
build/granboltz of the source tree the package is in."""

import os
import pathlib
import sys


def simulator():
    """The simulator's path, or None."""
    here = pathlib.Path(__file__).resolve().parents[1]  # the package granboltz
    for candidate in (here / "_bin" / "granboltz", here.parents[2] / "build" / "granboltz"):
        if candidate.is_file() and os.access(candidate, os.X_OK):
            return str(candidate)
    return None


def main():
    """`granboltz ARGS`: replaces this process by the simulator with the same arguments."""
    binary = simulator()
    if binary is None:
        here = pathlib.Path(__file__).resolve().parents[1]  # the package granboltz
        sys.exit(f"granboltz: no simulator next to the package ({here / '_bin'}) nor in its source tree's build/ "
                 "(make build, or pip install . to build one)")
    os.execv(binary, [binary, *sys.argv[1:]])
