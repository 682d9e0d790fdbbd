"""docs/python.md: its worked example runs exactly as written (the config block saved under its
name, the shell block with bash from a directory where build/granboltz is the built simulator,
the Python blocks in one /usr/bin/python3 process), and the figure it promises is written; every
module of the package is in its Modules table, and every public function and class of the
modules it documents in full is named on the page."""

import importlib
import inspect
import os
import pkgutil
import re
import subprocess
import sys

import pytest

import granboltz
from conftest import ROOT

DOC = ROOT / "docs" / "python.md"
BINARY = os.environ.get("GRANBOLTZ_BIN", str(ROOT / "build" / "granboltz"))


def code_blocks(text, section):
    """(language, info, code) of every fenced block in the section that starts with `section`."""
    start = text.index(section)
    end = text.find("\n## ", start + len(section))
    body = text[start:end if end > 0 else None]
    return [(m.group(1), m.group(2).strip(), m.group(3)) for m in
            re.finditer(r"^```(\w+)([^\n]*)\n(.*?)^```$", body, flags=re.M | re.S)]


def test_the_worked_example_has_a_config_a_command_and_python():
    kinds = [lang for lang, _, _ in code_blocks(DOC.read_text(), "## Worked example")]
    assert kinds == ["yaml", "sh", "python", "text"]


def test_the_worked_example_runs_as_written(tmp_path):
    if not os.access(BINARY, os.X_OK):
        pytest.fail(f"{BINARY} is missing: build the simulator first (make build)")
    (tmp_path / "build").mkdir()
    os.symlink(BINARY, tmp_path / "build" / "granboltz")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT / "src" / "python"), os.environ.get("PYTHONPATH", "")]))
    python, printed = [], None
    for lang, info, code in code_blocks(DOC.read_text(), "## Worked example"):
        if lang == "yaml":
            (tmp_path / re.fullmatch(r"file=(\S+)", info).group(1)).write_text(code)
        elif lang == "sh":
            subprocess.run(["bash", "-euo", "pipefail", "-c", code], cwd=tmp_path, env=env, check=True)
        elif lang == "python":
            python.append(code)
        else:
            printed = code
    out = subprocess.run([sys.executable, "-c", "\n".join(python)], cwd=tmp_path, env=env, check=True,
                         capture_output=True, text=True)
    assert out.stdout == printed  # what the page says it prints
    T, ci, exact = map(float, re.search(r"T\(4\) = (\S+) ± (\S+), exact (\S+)", out.stdout).groups())
    assert abs(T - exact) <= ci  # the 99.9 % band holds the exact value at this seed
    png = tmp_path / "example.png"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


# the modules whose every public function and class docs/python.md names (the others: their table row)
DOCUMENTED_IN_FULL = ["granboltz.theory.sonine", "granboltz.analysis.finite_size", "granboltz.output.summary", "granboltz.theory.closed_forms"]


def public_names(module_name):
    module = importlib.import_module(module_name)
    return [name for name, obj in vars(module).items() if not name.startswith("_")
            and getattr(obj, "__module__", None) == module_name and (inspect.isfunction(obj) or inspect.isclass(obj))]


def test_every_module_of_the_package_is_in_the_modules_table():
    text = DOC.read_text()
    table = text[text.index("## Modules"):]
    listed = set(re.findall(r"`(granboltz(?:\.\w+)+)`", table))
    modules = {m.name for m in pkgutil.walk_packages(granboltz.__path__, "granboltz.")}
    assert not modules - listed, f"not in the Modules table of docs/python.md: {sorted(modules - listed)}"
    assert not listed - modules, f"listed but not modules: {sorted(listed - modules)}"


@pytest.mark.parametrize("module_name", DOCUMENTED_IN_FULL)
def test_every_public_function_of_the_fully_documented_modules_is_named(module_name):
    text = DOC.read_text()
    missing = [name for name in public_names(module_name) if not re.search(rf"`{name}[`(]", text)]
    assert not missing, f"{module_name}: not named in docs/python.md: {missing}"
