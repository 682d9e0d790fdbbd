"""A smoke run of the fuzzer's study family (tests/fuzz/study_files.py): the first 24 study-file
cases and the first 6 table cases of a damaged study folder of a fixed seed pass the oracle.
The full family runs with `tests/fuzz/fuzz.py --families study` (tests/fuzz/README.md)."""

import random
import sys
import types

from conftest import ROOT
from test_study import BINARY, need_binary

sys.path.insert(0, str(ROOT / "tests" / "fuzz"))
import study_files  # noqa: E402

SEED = 11


def cases(kind, command, n):
    found, k = [], 0
    while len(found) < n:
        case = study_files.study_case(random.Random(f"{SEED}:{k}"))
        if case["kind"] == kind and case["command"] in command:
            found.append((k, case))
        k += 1
    return found


def test_study_files_and_damaged_folders_pass_the_fuzzer_oracle():
    need_binary()
    fz = types.SimpleNamespace(binary=BINARY, verbose=False)
    failed = []
    for k, case in cases("file", ("run", "table"), 24) + cases("folder", ("table",), 6):
        problem = study_files.run_case(fz, case)
        if problem:
            failed.append(f"case {k} ({case['kind']} {case['command']}: {case['note'][:60]}): {problem}")
    assert not failed, "\n".join(failed)
