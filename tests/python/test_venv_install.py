"""`pip install .` into a virtual environment (setup.py): offline, with Debian's setuptools, the
simulator compiled through CMake into the installed package. The environment imports its own
copy, runs the simulator in-process and as the `granboltz` command, and two checkouts installed
into two environments do not see each other. The installs reuse the CMake tree of `make build`
(GRANBOLTZ_CMAKE_BUILD_DIR), so nothing is compiled twice; setup.py's own tree is the same
CMake project configured apart."""

import os
import pathlib
import shutil
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
BUILD = ROOT / "build"

PROBE = r"""
import json, sys, granboltz
from granboltz.study.spec import find_binary
run = granboltz.simulate({"model": "dsmc", "seed": 1, "ensembles": 2, "dsmc": {"particles": 64, "alpha": 0.8,
    "beta": 1, "kernel": {"lambda": 0, "C": 0.0795774715459477}, "t_end": 1, "observe_every": 0.5}},
    progress=False)
import granboltz._core, granboltz.output.frames, granboltz.transport
print(json.dumps({"file": granboltz.__file__, "T": list(run.temperature.mean), "binary": find_binary(),
                  "checkout": getattr(granboltz, "CHECKOUT", None), "path": sys.path,
                  "modules": [m.__file__ for m in (granboltz._core, granboltz.output.frames, granboltz.transport)]}))
"""


def _install(source, venv):
    subprocess.run(["/usr/bin/python3", "-m", "venv", "--system-site-packages", str(venv)], check=True)
    env = dict(os.environ, GRANBOLTZ_CMAKE_BUILD_DIR=str(BUILD), PIP_NO_INDEX="1")
    env.pop("PYTHONPATH", None)
    subprocess.run([str(venv / "bin" / "pip"), "install", "-q", "--no-build-isolation", "--no-deps", str(source)],
                   check=True, env=env, cwd=source)


def _probe(venv, cwd):
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    out = subprocess.run([str(venv / "bin" / "python"), "-c", PROBE], check=True, capture_output=True, text=True,
                         env=env, cwd=cwd)
    import json

    return json.loads(out.stdout)


@pytest.mark.skipif(not (BUILD / "CMakeCache.txt").is_file(), reason="needs make build")
def test_two_checkouts_in_two_environments(tmp_path):
    # A second checkout: what pip reads of one (the CMake tree is reused, so no C++ sources).
    other = tmp_path / "other"
    skip = shutil.ignore_patterns("*.so", "__pycache__", "*.egg-info")
    for part in ("setup.py", "pyproject.toml", "docs/python.md", "src/python"):
        (other / part).parent.mkdir(parents=True, exist_ok=True)
        if (ROOT / part).is_dir():
            shutil.copytree(ROOT / part, other / part, ignore=skip)
        else:
            shutil.copy2(ROOT / part, other / part)
    # A mark that only the second checkout's package has.
    init = other / "src" / "python" / "granboltz" / "__init__.py"
    init.write_text(init.read_text() + '\nCHECKOUT = "other"\n')
    a, b = tmp_path / "venv-a", tmp_path / "venv-b"
    _install(ROOT, a)
    _install(other, b)
    pa, pb = _probe(a, tmp_path), _probe(b, tmp_path)
    for probe, venv in ((pa, a), (pb, b)):
        assert probe["file"].startswith(str(venv)), probe["file"]  # the installed copy, not a tree
        assert probe["binary"].startswith(str(venv)) and probe["binary"].endswith("_bin/granboltz")
        assert all(m.startswith(str(venv)) for m in probe["modules"]), probe["modules"]
        # An editable `make python` (--user) may put the tree on sys.path too: the environment's
        # own site-packages must come first, so that its copy is the one imported.
        own = min(i for i, p in enumerate(probe["path"]) if p.startswith(str(venv)))
        tree = [i for i, p in enumerate(probe["path"]) if p.startswith(str(ROOT / "src"))]
        assert all(own < i for i in tree), probe["path"]
    assert pa["checkout"] is None and pb["checkout"] == "other"
    assert pa["T"] == pb["T"] and len(pa["T"]) == 3  # the same simulator, the same bits
    version = subprocess.run([str(a / "bin" / "granboltz"), "--version"], check=True, capture_output=True,
                             text=True, cwd=tmp_path)
    assert version.stdout.startswith("granboltz ")
    # Nothing was written into the source tree's package (the extension link is make python's).
    assert not (ROOT / "src" / "python" / "granboltz" / "_bin").exists()
