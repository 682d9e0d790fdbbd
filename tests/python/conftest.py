"""Shared fixtures of the workflow tests: paths, a runner for workflow scripts with a stand-in
`snakemake` object, and synthetic granboltz output files with known answers."""

import pathlib
import runpy
import sys
import types

import h5py
import numpy as np
import pytest
import yaml

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCRIPTS = ROOT / "workflow" / "scripts"
sys.path.insert(0, str(SCRIPTS))

import granboltz_common as gc  # noqa: E402

# GRW05 Example 3 (§5.2): T(t) = e^{-3t/4} + 8/3 (1 - e^{-3t/4}), eq. (34)
EX3 = {"alpha": 0.5, "beta": 1.0, "gamma": 4.0, "kernel": {"lambda": 0, "C": 1 / (4 * np.pi)}}


def eq34(t):
    return np.exp(-0.75 * t) + 8.0 / 3.0 * (1.0 - np.exp(-0.75 * t))


def write_fake_run(path, n, N=100, eps=0.0, eps_centred=0.0, peak=None, V=None, t_end=8.0, dt=0.25,
                   kernel_lambda=0):
    """A granboltz-like output of Example 3 whose temperature is eq. (34) times (1 + eps).

    With `peak` = m, the relative error is eps at t_m and eps/2 elsewhere. V: [M+1, 3] bulk
    velocity (zero by default). ci = 0.01 T (uncentred) and 0.02 T (centred).
    """
    time = np.arange(0.0, t_end + dt / 2, dt)
    exact = eq34(time)
    shape = np.full_like(time, 1.0 if peak is None else 0.5)
    if peak is not None:
        shape[peak] = 1.0
    dsmc = dict(EX3, particles=n, scheme="nosplit", initial={"temperature": 1.0}, t_end=t_end,
                observe_every=dt)
    dsmc["kernel"] = dict(EX3["kernel"], **{"lambda": kernel_lambda})
    config = {"model": "dsmc", "seed": 1, "ensembles": N, "dsmc": dsmc}
    with h5py.File(path, "w") as f:
        f.attrs["config"] = yaml.safe_dump(config)
        f.attrs["ensembles"] = N
        f["time"] = time
        for name, e, rel_ci in (("temperature_uncentred", eps, 0.01), ("temperature", eps_centred, 0.02)):
            mean = exact * (1.0 + e * shape)
            f[f"{name}/mean"] = mean
            f[f"{name}/ci"] = rel_ci * exact
            f[f"{name}/variance"] = np.zeros_like(time)
        f["bulk_velocity/mean"] = np.zeros((time.size, 3)) if V is None else V
    return path


@pytest.fixture
def fake_run(tmp_path):
    """Factory: fake_run(n, **kwargs) -> path of a synthetic run file in tmp_path."""

    def make(n, **kwargs):
        return str(write_fake_run(tmp_path / f"n={n}.h5", n, **kwargs))

    return make


@pytest.fixture
def run_script(tmp_path):
    """Run workflow/scripts/NAME with a stand-in `snakemake` object, as Snakemake's script:
    directive does; returns the log text. input/output/params are dicts of named entries."""

    def run(name, input=None, output=None, params=None, wildcards=None):
        log = tmp_path / f"{name}.log"
        smk = types.SimpleNamespace(
            input=types.SimpleNamespace(**(input or {})),
            output=types.SimpleNamespace(**(output or {})),
            params=types.SimpleNamespace(**(params or {})),
            wildcards=types.SimpleNamespace(**(wildcards or {})),
            log=[str(log)],
        )
        saved = sys.stderr
        try:
            runpy.run_path(str(SCRIPTS / name), init_globals={"snakemake": smk}, run_name="__main__")
        finally:
            if sys.stderr is not saved:
                sys.stderr.close()
            sys.stderr = saved
        return log.read_text()

    return run
