"""No tracked file cites an issue number ("issue 10", "(issue 11)", "issues 12-14"): a comment,
docstring, page or report sentence says what a feature is and why, not which ticket asked for it.
The published paper/ folder (republished as a whole by `make paper`) and this test are exempt."""

import re
import subprocess

from conftest import ROOT

PATTERN = re.compile(r"\bissues? \d", re.IGNORECASE)
EXEMPT = ("paper/", "tests/python/test_no_issue_citations.py")


def tracked_files():
    out = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, check=True).stdout
    return [p for p in out.decode().split("\0") if p and not p.startswith(EXEMPT)]


def test_no_tracked_file_cites_an_issue_number():
    hits = []
    for name in tracked_files():
        path = ROOT / name
        if not path.is_file():  # deleted in the work tree, not yet in the index
            continue
        try:
            text = path.read_text(encoding="utf-8")
        except UnicodeDecodeError:  # binary (figures, HDF5 fixtures)
            continue
        for number, line in enumerate(text.splitlines(), 1):
            if PATTERN.search(line):
                hits.append(f"{name}:{number}: {line.strip()[:120]}")
    assert not hits, "issue numbers cited (say what and why instead):\n" + "\n".join(hits)
