"""A short run of the fuzzer's Python API family (tests/fuzz/python_api.py): 40 cases of a fixed
seed through simulate, Simulation, save, restore and two threads, every one passing the oracle
(documented exceptions with one-line messages, no hang, nothing left behind, inputs unchanged)."""

import subprocess
import sys

from conftest import ROOT


def test_the_python_api_family_passes_its_oracle(tmp_path):
    r = subprocess.run([sys.executable, str(ROOT / "tests" / "fuzz" / "fuzz.py"), "--families", "python",
                        "--seed", "20261204", "--cases", "40", "--no-corpus", "--findings", str(tmp_path)],
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-2000:]
    assert "40 cases" in r.stdout and "0 failing" in r.stdout, r.stdout[-2000:]
