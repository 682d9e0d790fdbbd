"""Shared fixtures of the workflow tests: paths, a runner for workflow scripts with a stand-in
`snakemake` object, and synthetic granboltz output files with known answers."""

import os
import pathlib
import runpy
import subprocess
import sys
import types

import h5py
import numpy as np
import pytest
import yaml

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCRIPTS = ROOT / "workflow" / "scripts"
# the simulator and the base configs of tests/bad_inputs/, shared by the tests that run it
BINARY = os.environ.get("GRANBOLTZ_BIN", str(ROOT / "build" / "granboltz"))
BASE = ROOT / "tests" / "bad_inputs" / "base"
# the granboltz package from this source tree, ahead of any installed copy
sys.path.insert(0, str(ROOT / "src" / "python"))

from granboltz.theory import scheme_temperature, uncentred_expectation

def merge_config(base, over):
    """over merged into base as Snakemake merges config files: dicts key by key, lists replaced."""
    for key, value in over.items():
        if isinstance(value, dict) and isinstance(base.get(key), dict):
            merge_config(base[key], value)
        else:
            base[key] = value
    return base


def load_config(profile):
    """The workflow's config of a profile: config/physics.yaml with config/<profile>.yaml over it."""
    physics = yaml.safe_load((ROOT / "config" / "physics.yaml").read_text())
    return merge_config(physics, yaml.safe_load((ROOT / "config" / f"{profile}.yaml").read_text()))


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
        f.attrs["version"], f.attrs["git_sha"] = "0.1.0", "abc123"
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


# ----------------------------------------------------------------------------- more fake outputs
RW05 = {"alpha": 0.5, "beta": 1.0, "gamma": 1.0, "kernel": {"lambda": 0, "C": 1 / np.pi}}


def _attrs(f, config, N, wall=1.0):
    f.attrs["config"] = yaml.safe_dump(config)
    f.attrs["ensembles"] = N
    f.attrs["version"] = "0.1.0"
    f.attrs["git_sha"] = "abc123"
    prov = f.create_group("provenance")
    prov.attrs["wall_seconds"] = wall


def write_fake_scheme_run(path, n, scheme, K, N=100, t_end=8.0, rel_ci=0.001):
    """An RW05 run of the Euler or Strang scheme (K steps on [0, t_end], observed at every step)
    whose uncentred temperature is exactly the scheme's expectation (granboltz.theory)."""
    dt = t_end / K
    time = np.arange(K + 1) * dt
    T = uncentred_expectation(scheme_temperature(scheme, time, dt, 1.0, 0.5, 1.0, 1.0, 1 / np.pi), time, 1.0,
                                 1.0, n)
    dsmc = dict(RW05, particles=n, scheme=scheme, steps=K, initial={"temperature": 1.0}, t_end=t_end,
                observe_every=dt)
    with h5py.File(path, "w") as f:
        _attrs(f, {"model": "dsmc", "seed": 1, "ensembles": N, "dsmc": dsmc}, N)
        f["time"] = time
        for name in ("temperature_uncentred", "temperature"):
            f[f"{name}/mean"] = T
            f[f"{name}/ci"] = rel_ci * T
        f["bulk_velocity/mean"] = np.zeros((time.size, 3))
    return path


def write_fake_steady_run(path, n, scheme="nosplit", K=None, T_inf=2.67, ci=0.004, wall=1.0, beta=1.0,
                          events=(1000, 0, 3000), series=None, N=1, batch=None):
    """A steady-state run of RW05 §4.2 (t_end = 136, observe_every = 2, steady_from = 8); batch =
    (ci, sigma[, tau_int]): the batch subgroup of steady_ci: independent (blocking) of T_inf."""
    time = np.arange(0.0, 136.0 + 1.0, 2.0)
    dsmc = dict(RW05, beta=beta, particles=n, scheme=scheme, initial={"temperature": 1.0}, t_end=136.0,
                observe_every=2.0, steady_from=8.0)
    if K is not None:
        dsmc["steps"] = 17 * K
    rng = np.random.default_rng(K or 0)
    s = series if series is not None else T_inf + 0.01 * rng.standard_normal(time.size)
    with h5py.File(path, "w") as f:
        _attrs(f, {"model": "dsmc", "seed": 1, "ensembles": N, "dsmc": dsmc}, N, wall)
        f["time"] = time
        f["temperature_uncentred/mean"] = s
        f["temperature/mean"] = s
        f["steady/temperature_uncentred/mean"] = T_inf
        f["steady/temperature_uncentred/ci"] = ci
        if batch is not None:
            f["steady/temperature_uncentred"].attrs["estimator"] = "independent"
            f["steady/temperature_uncentred/batch/ci"], f["steady/temperature_uncentred/batch/sigma"] = batch[:2]
            f["steady/temperature_uncentred/batch"].attrs["estimator"] = "blocking"
            if len(batch) > 2:
                f["steady/temperature_uncentred/batch"].attrs["tau_int"] = batch[2]
        f["steady/temperature/mean"] = T_inf - 0.001
        for key, value in zip(("collisions", "fictitious", "kicks"), events):
            f[f"events/{key}"] = np.full(N, value, dtype=np.uint64)
    return path


def tail_histogram(K=128, R=40.0, a=0.5, b=1.0, k0=1, total=None, seed=1):
    """Shell fractions (GRW05 eq. 37) whose density is c exp(-a ((k - k0) h)^b) for k >= k0 (eq.
    38 exactly) and a flat core below; with `total`, multinomial counts of that many particles."""
    edges = np.linspace(0.0, R, K + 1)
    h = R / K
    k = np.arange(1, K + 1)
    density = np.exp(-a * (np.maximum(k - k0, 0) * h) ** b)
    p = density * 4 * np.pi / 3 * (edges[1:] ** 3 - edges[:-1] ** 3)
    p = np.append(p, 0.0) / p.sum()
    if total is None:
        return edges, p, np.rint(p * 1e12).astype(np.uint64)
    counts = np.random.default_rng(seed).multinomial(total, p)
    return edges, counts / total, counts.astype(np.uint64)


def write_fake_histogram_run(path, lam=0.0, R=40.0, a=0.5, b=1.0, total=None, n=1000000, N=8, t_end=2.5,
                             steady=False):
    """A tail run (GRW05 §5.3) with the histogram of tail_histogram at the final time and a
    Maxwellian-like one at t = 0; steady=True: also as the steady histogram (steady_from = t_end/2)."""
    edges, final, counts = tail_histogram(R=R, a=a, b=b, total=total)
    initial = np.exp(-edges[1:] ** 2 / 2) * edges[1:] ** 2
    initial = np.append(initial / initial.sum(), 0.0)
    dsmc = {"particles": n, "scheme": "nosplit", "alpha": 0.1, "beta": 30.0, "gamma": 16.0,
            "kernel": {"lambda": lam, "C": 1 / (4 * np.pi)}, "initial": {"temperature": 1.0}, "t_end": t_end,
            "observe_every": t_end, "histogram": {"shells": edges.size - 1, "radius": R}}
    if steady:
        dsmc["steady_from"] = t_end / 2
    with h5py.File(path, "w") as f:
        _attrs(f, {"model": "dsmc", "seed": 1, "ensembles": N, "dsmc": dsmc}, N)
        f["time"] = np.array([0.0, t_end])
        f["temperature/mean"] = np.array([1.0, 15.0])
        f["histogram/edges"] = edges
        f["histogram/mean"] = np.vstack([initial, final])
        f["histogram/counts"] = np.vstack([np.rint(initial * n * N), counts]).astype(np.uint64)
        f.attrs["confidence_lambda_p"] = 3.2  # multinomial standard errors of the fractions, times lambda_p
        f["histogram/ci"] = 3.2 * np.sqrt(f["histogram/mean"][()] * (1 - f["histogram/mean"][()]) / (n * N))
        if steady:
            f["steady/histogram/mean"] = f["histogram/mean"][1]
            f["steady/histogram/ci"] = f["histogram/ci"][1]
    return path


def add_moments(path, crit_value=0.1):
    """Add the moments behind Crit (RW05 eq. 29) to a fake run: P = T I, q = 0 and a fourth
    moment gamma with Crit = |gamma| / (sqrt(120) T^2) = crit_value."""
    with h5py.File(path, "a") as f:
        T = f["temperature/mean"][()]
        M = T.size
        f["pressure_tensor/mean"] = T[:, None, None] * np.eye(3)[None]
        f["heat_flux/mean"] = np.zeros((M, 3))
        f["fourth_moment/mean"] = crit_value * np.sqrt(120.0) * T**2
        f["fourth_moment/ci"] = 0.01 * np.sqrt(120.0) * T**2
        f["crit/mean"] = np.full(M, crit_value + 0.05)
        f["crit/ci"] = np.full(M, 0.01)
    return path


def run_binary(*args, **kwargs):
    """The simulator with these arguments (a test fails, not skips, when it is not built)."""
    if not os.access(BINARY, os.X_OK):
        pytest.fail(f"{BINARY} is missing: build the simulator first (make build)")
    return subprocess.run([BINARY, *map(str, args)], check=True, **kwargs)
