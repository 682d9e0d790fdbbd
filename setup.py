"""`pip install .`: the package of src/python plus the simulator, both compiled by CMake.

Offline, into a virtual environment that sees Debian's packages (docs/python.md, "Install"):

    python3 -m venv --system-site-packages .venv
    .venv/bin/pip install --no-build-isolation .

The build configures its own CMake tree, build/pip-<python>/ of this checkout (Release, no tests
or benchmarks, ccache if present), builds the extension granboltz._core and the executable, and
puts both into the installed package (the executable as granboltz/_bin/granboltz, run by the
`granboltz` command of the environment). Nothing is linked into the source tree, so two checkouts
installed into two environments do not see each other. GRANBOLTZ_CMAKE_BUILD_DIR=DIR builds in
an existing CMake tree instead (e.g. build/ of `make build`: no second compilation).
"""

import glob
import os
import shutil
import subprocess
import sys
import sysconfig

from setuptools import Distribution, setup
from setuptools.command.build_py import build_py

ROOT = os.path.dirname(os.path.abspath(__file__))


def _cmake_tree():
    given = os.environ.get("GRANBOLTZ_CMAKE_BUILD_DIR")
    if given:
        tree = os.path.abspath(given)
        if not os.path.isfile(os.path.join(tree, "CMakeCache.txt")):
            sys.exit(f"GRANBOLTZ_CMAKE_BUILD_DIR={given}: not a configured CMake build tree")
        return tree
    tree = os.path.join(ROOT, "build", "pip-" + sysconfig.get_config_var("SOABI"))
    args = ["cmake", "-S", ROOT, "-B", tree, "-DCMAKE_BUILD_TYPE=Release", "-DGRANBOLTZ_TESTS=OFF",
            "-DGRANBOLTZ_BENCH=OFF", "-DGRANBOLTZ_PYTHON=ON", "-DGRANBOLTZ_PYTHON_LINK=OFF",
            f"-DPython_EXECUTABLE={sys.executable}"]
    if shutil.which("ccache"):
        args.append("-DCMAKE_CXX_COMPILER_LAUNCHER=ccache")
    subprocess.run(args, check=True)
    return tree


class BuildWithCMake(build_py):
    """build_py, then the simulator and its extension into the built package."""

    def run(self):
        super().run()
        if getattr(self, "editable_mode", False):
            return  # make python: the package imports the extension that make build links into it
        tree = _cmake_tree()
        jobs = os.environ.get("GRANBOLTZ_JOBS", str(min(os.cpu_count() or 1, 2)))
        subprocess.run(["cmake", "--build", tree, "-j", jobs, "--target", "granboltz", "granboltz_core"],
                       check=True)
        package = os.path.join(self.build_lib, "granboltz")
        extensions = glob.glob(os.path.join(tree, "python", "granboltz", "_core*.so"))
        if len(extensions) != 1:
            sys.exit(f"granboltz: expected one _core*.so in {tree}/python/granboltz, found {extensions}")
        shutil.copy2(extensions[0], package)
        os.makedirs(os.path.join(package, "_bin"), exist_ok=True)
        shutil.copy2(os.path.join(tree, "granboltz"), os.path.join(package, "_bin", "granboltz"))


class BinaryDistribution(Distribution):
    """A platform wheel: the package carries a compiled extension and executable."""

    def has_ext_modules(self):
        return True


# setuptools' own build folder beside the CMake trees, not inside build/ of `make build`.
setup(cmdclass={"build_py": BuildWithCMake}, distclass=BinaryDistribution,
      options={"build": {"build_base": os.path.join("build", "setuptools")}})
