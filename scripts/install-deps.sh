#!/usr/bin/env bash
# Installs granboltz's build and pipeline dependencies from Debian packages (no PyPI).
# Shared by `make reproduce`, `make test`, `make docs` and CI (the Sphinx ones: `make docs`, and
# nbclient/ipykernel: the tutorial notebook's test). Skips apt when everything is present.
# --with-browser adds Chromium, for the browser test of the HTML report (tests/python/
# test_report_browser.py): optional because it is large (124 MB download, 414 MB installed,
# ~1 min), installed by CI (.ci/run) and by `make deps-browser`.
set -euo pipefail

PACKAGES=(
  g++ cmake make pkg-config git
  libgsl-dev libhdf5-dev libyaml-cpp-dev libcli11-dev libgtest-dev libbenchmark-dev
  librandom123-dev
  snakemake python3-numpy python3-h5py python3-matplotlib python3-scipy python3-pytest
  python3-jsonschema python3-yaml python3-pandas python3-xarray python3-sympy python3-mpmath python3-setuptools python3-pip
  pybind11-dev python3-pybind11 python3-dev python3-tqdm
  clang-format
)
# The documentation (`make docs`: Sphinx, furo, myst-parser) and the tutorial notebook, run as a
# reader runs it (tests/python/test_tutorial.py: jupyter nbconvert --execute, ipykernel, and
# ipywidgets for the progress bar in a notebook); python3-venv for `pip install .` into a virtual
# environment (tests/python/test_venv_install.py).
PACKAGES+=(python3-sphinx furo python3-myst-parser python3-nbclient python3-ipykernel python3-nbformat
           jupyter-nbconvert python3-nbconvert python3-ipywidgets python3-venv)
BROWSER_PACKAGES=(chromium)
# --with-fuzz: AFL++ (and the clang it instruments with), for `make fuzz` only, never CI.
FUZZ_PACKAGES=(afl++ clang)
for arg in "$@"; do
  case "$arg" in
    --with-browser) PACKAGES+=("${BROWSER_PACKAGES[@]}") ;;
    --with-fuzz) PACKAGES+=("${FUZZ_PACKAGES[@]}") ;;
    *) echo "install-deps: unknown option '$arg' (allowed: --with-browser, --with-fuzz)" >&2; exit 2 ;;
  esac
done

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PACKAGES[@]} Debian packages present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install-deps: need root or sudo to apt-get install ${missing[*]}" >&2; exit 1; }
  SUDO=sudo
fi
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
