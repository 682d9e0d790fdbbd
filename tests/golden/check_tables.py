"""Compare the tables of a reproduction with golden copies, byte for byte.

    /usr/bin/python3 tests/golden/check_tables.py results/tables tests/golden/quick_tables

Every golden file (CSV and LaTeX) must exist in the results directory with identical bytes; the
results directory must hold no table the golden set lacks. The one exception is the columns that
hold measured wall times (TIMING_COLUMNS: the simulator's wall_seconds, the CPU ratios of RW05
Tables 3-6 and the effort table, TV06's ns per collision), which differ from run to run on any
machine: their cells are compared as "a number or empty on both sides", every other byte of
those files exactly. Prints one line per difference (and the first differing lines of each file)
and exits 1 if there is any. The golden files are the quick profile's tables (`make reproduce`);
the README says how to update them on purpose.
"""

import csv
import difflib
import io
import pathlib
import re
import sys

TABLE_SUFFIXES = (".csv", ".tex")
TIMING_COLUMNS = {"wall_seconds", "CPU", "CF_CPU", "ns_per_collision", "ns_gillespie", "ns_dsmc"}
_LATEX_TIMING = {name.replace("_", "\\_") for name in TIMING_COLUMNS}
_CELL = re.compile(r"[-+0-9.eE]+|nan|inf|--|")


def _mask(cell):
    """A timing cell as a placeholder: '<time>' for a number, '<none>' for an empty cell, and
    the cell itself otherwise (so a non-number still shows up as a difference)."""
    if not _CELL.fullmatch(cell):
        return cell
    return "<none>" if cell in ("", "--") else "<time>"


def masked(name, data):
    """The text of a table with the cells of its timing columns replaced by placeholders."""
    text = data.decode()
    if name.endswith(".csv"):
        rows = list(csv.reader(io.StringIO(text, newline="")))
        cols = [i for i, h in enumerate(rows[0]) if h in TIMING_COLUMNS] if rows else []
        if not cols:
            return text
        out = io.StringIO(newline="")
        writer = csv.writer(out, lineterminator="\n")
        writer.writerows([rows[0]] + [[_mask(c) if i in cols else c for i, c in enumerate(r)] for r in rows[1:]])
        return out.getvalue()
    lines = text.split("\n")
    try:  # booktabs: header row after \toprule, data rows between \midrule and \bottomrule
        head, start, end = lines.index("\\toprule") + 1, lines.index("\\midrule") + 1, lines.index("\\bottomrule")
    except ValueError:
        return text
    cols = [i for i, h in enumerate(lines[head].removesuffix(" \\\\").split(" & ")) if h in _LATEX_TIMING]
    for k in range(start, end) if cols else ():
        cells = lines[k].removesuffix(" \\\\").split(" & ")
        lines[k] = " & ".join(_mask(c) if i in cols else c for i, c in enumerate(cells)) + " \\\\"
    return "\n".join(lines)


def tables(directory):
    """{file name: path} of the CSV and LaTeX tables directly in `directory`."""
    return {p.name: p for p in sorted(pathlib.Path(directory).iterdir()) if p.suffix in TABLE_SUFFIXES}


def compare(results, golden, context_lines=6):
    """A list of human-readable differences between the two table directories (empty if equal)."""
    ours, want = tables(results), tables(golden)
    problems = [f"missing: {results}/{name} (golden {want[name]})" for name in sorted(want.keys() - ours.keys())]
    problems += [f"not in the golden set: {ours[name]}" for name in sorted(ours.keys() - want.keys())]
    for name in sorted(want.keys() & ours.keys()):
        a, b = want[name].read_bytes(), ours[name].read_bytes()
        if a != b and masked(name, a) != masked(name, b):
            diff = difflib.unified_diff(masked(name, a).splitlines(), masked(name, b).splitlines(),
                                        str(want[name]), str(ours[name]), lineterm="", n=0)
            problems.append(f"differs: {ours[name]}\n" + "\n".join(list(diff)[:context_lines + 2]))
    return problems


def main(argv):
    if len(argv) != 3:
        print(__doc__.strip().splitlines()[0], file=sys.stderr)
        print(f"usage: {argv[0]} RESULTS_TABLES_DIR GOLDEN_DIR", file=sys.stderr)
        return 2
    results, golden = argv[1], argv[2]
    for d in (results, golden):
        if not pathlib.Path(d).is_dir():
            print(f"check-tables: {d} is not a directory (run `make reproduce` first)", file=sys.stderr)
            return 2
    problems = compare(results, golden)
    for p in problems:
        print(f"check-tables: {p}", file=sys.stderr)
    n = len(tables(golden))
    if problems:
        print(f"check-tables: {len(problems)} difference(s) against {n} golden tables in {golden}", file=sys.stderr)
        return 1
    print(f"check-tables: {n} tables in {results} identical to {golden}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
