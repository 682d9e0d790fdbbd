#!/usr/bin/python3
"""The folders of src/granboltz/ are layers: a file includes its own folder and lower layers only,
so that no two folders depend on each other (no include cycles) and each builds on those below.
Checks every #include "granboltz/..." of src/ (headers, sources, the templates of the generated
headers); exit 1 with one line per include that points up or sideways.

    check_layers.py [SRC]           (default: this repository's src/)
    check_layers.py --dot [SRC]     the folder include graph in Graphviz DOT, one rank per layer
                                    (| dot -Tsvg > layers.svg where Graphviz is installed)
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


def main(src, dot=False):
    src, bad, edges = pathlib.Path(src), [], set()
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
                if to in LAYERS and to != where:
                    edges.add((where, to))
                if to not in LAYERS:
                    bad.append(f"{path}:{n}: {m.group(1)} is not in a folder of the layer table")
                elif to != where and (LAYERS[to] > LAYERS[where] or (
                        LAYERS[to] == LAYERS[where] and (where, to) not in ALLOWED)):
                    kind = "a higher layer" if LAYERS[to] > LAYERS[where] else "sideways"
                    bad.append(f"{path}:{n}: {where} (L{LAYERS[where]}) includes {m.group(1)}: "
                               f"{kind} (L{LAYERS[to]})")
    if dot:
        print(graph(edges))
    else:
        print("\n".join(bad) if bad else f"include layers: {len(files)} files, all point down")
    return 1 if bad else 0


def graph(edges):
    """DOT of the folders, the higher layers on top, an edge per folder that includes another."""
    lines = ["digraph layers {", "  rankdir=TB; node [shape=box];"]
    for level in sorted(set(LAYERS.values()), reverse=True):
        names = " ".join(f'"{k}"' for k, v in LAYERS.items() if v == level)
        lines.append(f'  {{ rank=same; "L{level}" [shape=plaintext]; {names} }}')
    levels = sorted(set(LAYERS.values()), reverse=True)
    lines += [f'  "L{a}" -> "L{b}" [style=invis];' for a, b in zip(levels, levels[1:])]
    lines += [f'  "{a}" -> "{b}";' for a, b in sorted(edges)]
    return "\n".join(lines + ["}"])


if __name__ == "__main__":
    default = pathlib.Path(__file__).resolve().parents[1] / "src"
    args = [a for a in sys.argv[1:] if a != "--dot"]
    sys.exit(main(args[0] if args else default, dot="--dot" in sys.argv[1:]))
