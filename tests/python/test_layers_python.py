"""tests/check_layers_python.py: the package's layers hold, and each rule can fail."""

import subprocess
import sys

from conftest import ROOT

SCRIPT = ROOT / "tests" / "check_layers_python.py"


def check(package):
    return subprocess.run([sys.executable, str(SCRIPT), str(package)], capture_output=True, text=True)


def test_the_package_keeps_its_layers():
    result = check(ROOT / "src" / "python" / "granboltz")
    assert result.returncode == 0, result.stderr


def tiny_package(tmp_path, theory_text, top_text="X = 1\n"):
    root = tmp_path / "granboltz"
    (root / "theory").mkdir(parents=True)
    (root / "__init__.py").write_text("")
    (root / "top.py").write_text(top_text)
    (root / "theory" / "__init__.py").write_text("")
    (root / "theory" / "formulas.py").write_text(theory_text)
    return root


def test_each_rule_can_fail(tmp_path):
    assert check(tiny_package(tmp_path / "ok", "import math\n\nY = 2\n", "from .theory.formulas import Y\n")).returncode == 0
    for name, theory, top, message in [
            ("up", "from ..top import X\n", "X = 1\n", "layer 'theory' imports granboltz.top"),
            ("up_absolute", "from granboltz import top\n", "X = 1\n", "layer 'theory' imports granboltz.top"),
            ("private", "_Y = 2\n", "from .theory.formulas import _Y\n", "private name _Y"),
            ("file", "def f(p):\n    return open(p).read()\n", "X = 1\n", "opens a file"),
            ("h5py", "import h5py\n", "X = 1\n", "imports h5py"),
            ("verdict", "def a2_verdict(x):\n    return x\n", "X = 1\n", "has a verdict")]:
        result = check(tiny_package(tmp_path / name, theory, top))
        assert result.returncode == 1 and message in result.stderr, (name, result.stderr)
