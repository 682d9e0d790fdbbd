"""Compare the tables of a reproduction with golden copies, byte for byte.

    /usr/bin/python3 tests/golden/check_tables.py results/tables tests/golden/quick_tables

Every golden file (CSV and LaTeX) must exist in the results directory with identical bytes; the
results directory must hold no table the golden set lacks. Prints one line per difference (and
the first differing lines of each file) and exits 1 if there is any. The golden files are the
quick profile's tables (`make reproduce`); the README says how to update them on purpose.
"""

import difflib
import pathlib
import sys

TABLE_SUFFIXES = (".csv", ".tex")


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
        if a != b:
            diff = difflib.unified_diff(a.decode(errors="replace").splitlines(), b.decode(errors="replace").splitlines(),
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
