#!/usr/bin/python3
"""The folders of src/granboltz/ are layers: a file includes its own folder and lower layers only,
so that no two folders depend on each other (no include cycles) and each builds on those below.
Checks every #include "granboltz/..." of src/ (headers, sources, the templates of the generated
headers); exit 1 with one line per include that points up or sideways.

    check_layers.py [SRC]     (default: this repository's src/)
"""
import pathlib
import re
import sys

LAYERS = {"core": 0,                                      # hot.hpp, Vec3, uint128, GSL, version
          "random": 1, "stats": 1, "h5": 1, "config": 1,  # streams; exact sums; HDF5; Section
          "physics": 2, "record": 2,                      # kernels and kicks; the exact run state
          "exec": 3,                                      # the ensemble pool, RunFrame
          "dsmc": 4, "tv06": 4,                           # the models
          "app": 5,                                       # Config, model dispatch, output, merge
          "main.cpp": 6}                                  # src/main.cpp
ALLOWED = set()  # sideways includes (same layer, other folder) allowed, as (from, to): none
INCLUDE = re.compile(r'\s*#\s*include\s+"granboltz/([^"]+)"')


def main(src):
    src, bad = pathlib.Path(src), []
    files = [p for p in sorted(src.rglob("*")) if p.suffix in (".hpp", ".cpp", ".in")]
    for path in files:
        parts = path.relative_to(src).parts
        if parts[0] not in ("granboltz", "main.cpp"):
            continue
        where = parts[1] if parts[0] == "granboltz" and len(parts) > 2 else parts[-1]
        if where not in LAYERS:
            bad.append(f"{path}: not in a folder of the layer table")
            continue
        for n, line in enumerate(path.read_text().splitlines(), 1):
            if m := INCLUDE.match(line):
                to = m.group(1).split("/")[0] if "/" in m.group(1) else None
                if to not in LAYERS:
                    bad.append(f"{path}:{n}: {m.group(1)} is not in a folder of the layer table")
                elif to != where and (LAYERS[to] > LAYERS[where] or (
                        LAYERS[to] == LAYERS[where] and (where, to) not in ALLOWED)):
                    kind = "a higher layer" if LAYERS[to] > LAYERS[where] else "sideways"
                    bad.append(f"{path}:{n}: {where} (L{LAYERS[where]}) includes {m.group(1)}: "
                               f"{kind} (L{LAYERS[to]})")
    print("\n".join(bad) if bad else f"include layers: {len(files)} files, all point down")
    return 1 if bad else 0


if __name__ == "__main__":
    default = pathlib.Path(__file__).resolve().parents[1] / "src"
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else default))
