"""Shared by the workflow scripts: HDF5 reading, analytic formulas, the numbers of every GRW05
and RW05 table (convergence, time step, steady state, effort model, tail fits), plot style, and
atomic writing of outputs. (Report, Markdown/HTML and LaTeX writing: granboltz_report.py.)

The scripts import this module by name (Snakemake puts a script's directory on sys.path). It
never touches the `snakemake` object: every function takes plain paths and values, so the tests
call it directly.
"""

import contextlib
import csv
import json
import math
import os
import tempfile
from dataclasses import dataclass, field

import h5py
import numpy as np
import yaml

# Temperature estimator behind the published error tables: phi(v) = |v|^2 / 3 (RW05 §4.1). Its
# exact finite-n bias matches the published E_max (about 5.7/n in GRW05 Example 3); the centred
# temperature (GRW05 eq. 13) is biased by only about 1/n and is reported alongside.
TEMPERATURE = "temperature_uncentred"
TEMPERATURE_CENTRED = "temperature"
LAMBDA_P = 3.2  # confidence half-width factor of GRW05 §5.1 (p = 0.999)


# ----------------------------------------------------------------------------- output files
@contextlib.contextmanager
def atomic_path(path):
    """Yield a temporary name in the directory of `path`; rename it to `path` on success.

    A failed step leaves no half-written output: the temporary file is removed instead.
    """
    directory = os.path.dirname(os.path.abspath(path))
    os.makedirs(directory, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=directory, prefix="." + os.path.basename(path) + ".", suffix=".tmp")
    os.close(fd)
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o666 & ~umask)
    try:
        yield tmp
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.remove(tmp)
        raise


def write_csv(rows, columns, path, digits=4):
    """Write dict rows as CSV (floats with `digits` significant digits, None as empty), atomically."""

    def cell(value):
        if value is None:
            return ""
        if isinstance(value, (float, np.floating)):
            return f"{value:.{digits}g}" if math.isfinite(value) else "nan"
        return str(value)

    with atomic_path(path) as tmp:
        with open(tmp, "w", newline="") as out:
            writer = csv.writer(out, lineterminator="\n")
            writer.writerow(columns)
            for row in rows:
                writer.writerow([cell(row[c]) for c in columns])


def write_text(text, path):
    """Write a text file atomically."""
    with atomic_path(path) as tmp:
        with open(tmp, "w") as out:
            out.write(text)


def write_json(obj, path):
    """Write a JSON file (sorted keys, floats as they are), atomically."""
    write_text(json.dumps(obj, indent=1, sort_keys=True, default=float) + "\n", path)


def read_csv(path):
    """Rows of a CSV file as dicts of strings."""
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


# ----------------------------------------------------------------------------- simulator output
@dataclass
class Run:
    """The observables of one DSMC run (granboltz HDF5 output) needed by the GRW05/RW05 items."""

    path: str
    config: dict  # the run config, as stored in the file's root attribute `config`
    n: int  # particles per ensemble
    N: int  # ensembles
    time: np.ndarray  # observation times t_m, [M+1]
    T: np.ndarray  # mean of the uncentred temperature estimator, [M+1]
    T_ci: np.ndarray  # its confidence half-width (GRW05 eq. 31, lambda_p = 3.2), [M+1]
    T_centred: np.ndarray  # mean of the centred temperature (GRW05 eq. 13), [M+1]
    T_centred_ci: np.ndarray
    V: np.ndarray  # mean bulk velocity (GRW05 eq. 12), [M+1, 3]
    crit: np.ndarray = None  # Crit(t) of RW05 eq. (29) per ensemble, averaged, [M+1]
    crit_ci: np.ndarray = None
    moments: dict = None  # ensemble means (and ci) of pressure_tensor, heat_flux, fourth_moment
    attrs: dict = field(default_factory=dict)  # version, git_sha, wall_seconds

    @property
    def dsmc(self):
        return self.config["dsmc"]

    @property
    def scheme(self):
        return self.dsmc.get("scheme", "nosplit")

    @property
    def dt(self):
        """Time step of a splitting scheme (t_end / steps); None for no-splitting."""
        return None if self.scheme == "nosplit" else self.dsmc["t_end"] / self.dsmc["steps"]


def _text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def _finite(f, name, path):
    data = f[name][()]
    if not np.all(np.isfinite(data)):
        raise ValueError(f"{path}: dataset /{name} has non-finite values")
    return data


def run_attrs(f):
    """Provenance of an open output file: version, git_sha, wall_seconds (None if absent)."""
    prov = f["provenance"].attrs if "provenance" in f else {}
    wall = prov.get("wall_seconds")
    return {
        "version": _text(f.attrs.get("version", "")),
        "git_sha": _text(f.attrs.get("git_sha", "")),
        "wall_seconds": None if wall is None else float(wall),
    }


def read_run(path):
    """Read one granboltz DSMC output file into a Run; refuse non-finite values."""
    with h5py.File(path, "r") as f:
        config = yaml.safe_load(_text(f.attrs["config"]))
        crit = "crit/mean" in f
        names = ("pressure_tensor/mean", "heat_flux/mean", "fourth_moment/mean", "fourth_moment/ci")
        moments = {name: _finite(f, name, path) for name in names} if all(n in f for n in names) else None
        return Run(
            path=str(path),
            config=config,
            n=int(config["dsmc"]["particles"]),
            N=int(f.attrs["ensembles"]),
            time=_finite(f, "time", path),
            T=_finite(f, f"{TEMPERATURE}/mean", path),
            T_ci=_finite(f, f"{TEMPERATURE}/ci", path),
            T_centred=_finite(f, f"{TEMPERATURE_CENTRED}/mean", path),
            T_centred_ci=_finite(f, f"{TEMPERATURE_CENTRED}/ci", path),
            V=_finite(f, "bulk_velocity/mean", path),
            crit=_finite(f, "crit/mean", path) if crit else None,
            crit_ci=_finite(f, "crit/ci", path) if crit else None,
            moments=moments,
            attrs=run_attrs(f),
        )


def read_histogram(path):
    """The radial histogram of a run (GRW05 eq. 37): dict with edges [K+1], mean and counts
    [M+1, K+1] (last shell = |v| >= R), time, n, N, config."""
    with h5py.File(path, "r") as f:
        config = yaml.safe_load(_text(f.attrs["config"]))
        return {
            "edges": _finite(f, "histogram/edges", path),
            "mean": _finite(f, "histogram/mean", path),
            "counts": f["histogram/counts"][()],
            "time": _finite(f, "time", path),
            "T": _finite(f, f"{TEMPERATURE_CENTRED}/mean", path),
            "n": int(config["dsmc"]["particles"]),
            "N": int(f.attrs["ensembles"]),
            "config": config,
        }


def read_steady(path):
    """The steady-state averages of a run (RW05 §4.2) and its event counts: dict."""
    with h5py.File(path, "r") as f:
        config = yaml.safe_load(_text(f.attrs["config"]))
        if "steady" not in f:
            raise ValueError(f"{path}: no /steady group (run without dsmc.steady_from)")
        out = {
            "config": config,
            "n": int(config["dsmc"]["particles"]),
            "N": int(f.attrs["ensembles"]),
            "time": _finite(f, "time", path),
            "series": _finite(f, f"{TEMPERATURE}/mean", path),
            **{key: float(_finite(f, f"steady/{TEMPERATURE}/{key}", path)) for key in ("mean", "ci")},
            "mean_centred": float(_finite(f, f"steady/{TEMPERATURE_CENTRED}/mean", path)),
            **{f"events_{key}": f[f"events/{key}"][()].astype(float) for key in ("collisions", "fictitious", "kicks")},
            **run_attrs(f),
        }
        return out


def crit_of_means(run):
    """Crit(t) of RW05 eq. (29) evaluated at the ensemble means of the moments (the functional of
    the approximated solution, as the paper plots it), and an approximate confidence half-width
    from that of the fourth moment, the dominant term: (Crit, ci), each [M+1].

    Crit = (1/T) (1/2 |P - p I|_F^2 + 2/(5T) |q|^2 + gamma^2 / (120 T^2))^(1/2), p = tr P / 3.
    (The simulator's /crit is the mean of the per-ensemble Crit, biased upward by the sampling
    noise of n particles: about 1/sqrt(n) at t = 0.)"""
    P, q = run.moments["pressure_tensor/mean"], run.moments["heat_flux/mean"]
    g, g_ci, T = run.moments["fourth_moment/mean"], run.moments["fourth_moment/ci"], run.T_centred
    p = np.trace(P, axis1=1, axis2=2) / 3.0
    dev = P - p[:, None, None] * np.eye(3)
    crit = np.sqrt(0.5 * np.sum(dev**2, axis=(1, 2)) + 2.0 / (5.0 * T) * np.sum(q**2, axis=1)
                   + g**2 / (120.0 * T**2)) / T
    return crit, g_ci / (math.sqrt(120.0) * T**2)


# ----------------------------------------------------------------------------- analytic formulas
def analytic_temperature(t, T0, alpha, beta, gamma, C0):
    """Temperature of the heated Maxwell-pseudomolecule gas, GRW05 eqs. (16), (17).

    T(t) = T0 e^{-k t} + T_inf (1 - e^{-k t}), k = gamma pi C0 (1 - alpha^2), T_inf = 2 beta / k;
    for alpha = 1 (k = 0) the limit T0 + 2 beta t.
    """
    t = np.asarray(t, dtype=float)
    k = gamma * math.pi * C0 * (1.0 - alpha**2)
    if k == 0.0:
        return T0 + 2.0 * beta * t
    decay = np.exp(-k * t)
    return T0 * decay + (2.0 * beta / k) * (1.0 - decay)


def _physics(dsmc):
    """(T0, alpha, beta, gamma, C0) of a run config's dsmc section (lambda must be 0)."""
    if dsmc["kernel"]["lambda"] != 0:
        raise ValueError(f"eq. (16) needs kernel lambda = 0, got {dsmc['kernel']['lambda']}")
    T0 = dsmc.get("initial", {}).get("temperature", 1.0)
    return T0, dsmc["alpha"], dsmc["beta"], dsmc.get("gamma", 1.0), dsmc["kernel"]["C"]


def run_analytic_temperature(run):
    """Eq. (16) with the parameters the run was made with (lambda must be 0: eq. 16 is exact
    for Maxwell pseudomolecules only)."""
    try:
        return analytic_temperature(run.time, *_physics(run.dsmc))
    except ValueError as err:
        raise ValueError(f"{run.path}: {err}") from None


def scheme_temperature(scheme, t, dt, T0, alpha, beta, gamma, C0):
    """Mean temperature of a scheme as n -> infinity at the times t (multiples of dt), Maxwell
    molecules: no-splitting is eq. (16); one Euler step (RW05 Alg. 1: collisions, then kicks)
    maps T to e^{-k dt} T + 2 beta dt, one Strang step to e^{-k dt/2}(e^{-k dt/2} T + 2 beta dt),
    with k = gamma pi C0 (1 - alpha^2). Observations follow a whole step."""
    t = np.atleast_1d(np.asarray(t, dtype=float))
    if scheme == "nosplit":
        return analytic_temperature(t, T0, alpha, beta, gamma, C0)
    k = gamma * math.pi * C0 * (1.0 - alpha**2)
    a, b = math.exp(-k * dt), 2.0 * beta * dt
    if scheme == "strang":
        b *= math.exp(-k * dt / 2)
    elif scheme != "euler":
        raise ValueError(f"unknown scheme {scheme!r}")
    steps = np.rint(t / dt).astype(int)
    if np.any(np.abs(steps * dt - t) > 1e-9 * np.maximum(1.0, t)):
        raise ValueError("observation times must be multiples of dt")
    # T_k = a^k T0 + b (1 - a^k) / (1 - a)
    ak = a ** steps.astype(float)
    return ak * T0 + (b * steps if a == 1.0 else b * (1.0 - ak) / (1.0 - a))


def scheme_steady_temperature(scheme, dt, alpha, beta, gamma, C0):
    """Stationary mean temperature of a scheme as n -> infinity (fixed point of the step maps of
    scheme_temperature; no-splitting: T_inf = 2 beta / k, GRW05 eq. 17, RW05 eq. 25)."""
    k = gamma * math.pi * C0 * (1.0 - alpha**2)
    if scheme == "nosplit":
        return 2.0 * beta / k
    T = 2.0 * beta * dt / (1.0 - math.exp(-k * dt))
    return T * math.exp(-k * dt / 2) if scheme == "strang" else T


def uncentred_expectation(T_mean, t, T0, beta, n):
    """E of the uncentred estimator |v|^2/3 of an n-particle system whose mean temperature (n ->
    infinity) is T_mean at time t: (1 - 1/n) T_mean + (T0 + 2 beta t)/n. The centred part has
    the exact bias -T/n (Maxwell molecules); |V|^2/3 adds (T0 + 2 beta t)/n, since collisions
    conserve momentum and the kicks make V a random walk of variance 2 beta t/n per component."""
    return (1.0 - 1.0 / n) * np.asarray(T_mean) + (T0 + 2.0 * beta * np.asarray(t)) / n


def expected_error(run):
    """max_m |E T_m - T(t_m)| / T(t_m): the relative error of the uncentred estimator the run's
    scheme would have with N -> infinity (the systematic part of E_max), and the same at t_end."""
    T0, alpha, beta, gamma, C0 = _physics(run.dsmc)
    exact = run_analytic_temperature(run)
    mean = scheme_temperature(run.scheme, run.time, run.dt, T0, alpha, beta, gamma, C0)
    err = np.abs(uncentred_expectation(mean, run.time, T0, beta, run.n) - exact) / exact
    return float(err.max()), float(err[-1])


def _cf(rows, key, cf):
    """CF columns: quotient of consecutive values of `key` (previous / this), None in row one."""
    for prev, row in zip([None] + rows[:-1], rows):
        row[cf] = None if prev is None or not row[key] else prev[key] / row[key]


# ----------------------------------------------------------------------------- GRW05 Tables 1, 2
TABLE_COLUMNS = [
    *["n", "N", "E_max", "CF", "V_inf"],  # the paper's columns, and N
    *["E_max_ci", "t_Emax", "Conf_end", "E_max_expected", "E_max_centred", "CF_centred"],  # ours
]


def _sorted_unique(runs, key, what="n"):
    runs = sorted(runs, key=key)
    if len({key(r) for r in runs}) != len(runs):
        raise ValueError(f"two runs with the same {what}: " + ", ".join(r.path for r in runs))
    return runs


def convergence_rows(runs):
    """Rows of GRW05 Tables 1/2 (and RW05 Table 1's E_max), one per run, sorted by n.

    E_max = max_m |T_m - T(t_m)| / T(t_m) (GRW05 eq. 35) of the uncentred estimator; CF =
    E_max of the previous row / E_max; V_inf = max_m |V(t_m)|; E_max_ci = ci / T(t) at t_Emax,
    the time of the maximal error; Conf_end = ci / T(t) at the last time; E_max_expected = the
    exact systematic part (expected_error); E_max_centred and CF_centred: the same error for the
    centred temperature (eq. 13).
    """
    rows = []
    for run in _sorted_unique(runs, lambda r: r.n):
        exact = run_analytic_temperature(run)
        error = np.abs(run.T - exact) / exact
        m = int(np.argmax(error))
        rows.append(
            {
                "n": run.n,
                "N": run.N,
                "E_max": float(error[m]),
                "V_inf": float(np.max(np.linalg.norm(run.V, axis=1))),
                "E_max_ci": float(run.T_ci[m] / exact[m]),
                "t_Emax": float(run.time[m]),
                "Conf_end": float(run.T_ci[-1] / exact[-1]),
                "E_max_expected": expected_error(run)[0],
                "E_max_centred": float(np.max(np.abs(run.T_centred - exact) / exact)),
            }
        )
    _cf(rows, "E_max", "CF")
    _cf(rows, "E_max_centred", "CF_centred")
    return rows


# ----------------------------------------------------------------------------- RW05 Tables 1, 2
RW05_TABLE1_COLUMNS = [
    *["n", "E_end", "CF_E_end", "Conf_end", "CF_Conf_end", "E_max", "CF_E_max"],  # the paper's
    *["N", "T_end_exact", "E_end_expected", "E_max_ci", "t_Emax", "E_max_expected", "E_end_centred"],  # ours
]


def rw05_table1_rows(runs):
    """RW05 Table 1: E_end, E_max (relative errors of T against eq. 28 at t_K and over all t_k),
    Conf_end (relative confidence half-width at t_K, lambda_p = 3.2) and their CFs, one row per n."""
    rows = convergence_rows(runs)
    for row, run in zip(rows, _sorted_unique(runs, lambda r: r.n)):
        exact = run_analytic_temperature(run)
        row["E_end"] = float(abs(run.T[-1] - exact[-1]) / exact[-1])
        row["T_end_exact"] = float(exact[-1])
        row["E_end_expected"] = expected_error(run)[1]
        row["E_end_centred"] = float(abs(run.T_centred[-1] - exact[-1]) / exact[-1])
    for key in ("E_end", "Conf_end", "E_max"):
        _cf(rows, key, "CF_" + key)
    return rows


RW05_TABLE2_COLUMNS = [
    *["K", "E_max_euler", "CF_euler", "E_max_strang", "CF_strang"],  # the paper's
    *["n", "N", "E_max_euler_ci", "E_max_strang_ci", "E_expected_euler", "E_expected_strang"],  # ours
]


def timestep_rows(euler, strang, dt_unit):
    """RW05 Table 2: E_max of the Euler and Strang runs (observed at every t_k) per K = dt_unit/dt;
    E_expected_*: the systematic part (time step and finite n, N -> infinity)."""
    by_K = {}
    for scheme, runs in (("euler", euler), ("strang", strang)):
        for run in _sorted_unique(runs, lambda r: r.dt, "time step"):
            if run.scheme != scheme:
                raise ValueError(f"{run.path}: scheme {run.scheme}, expected {scheme}")
            K = int(round(dt_unit / run.dt))
            (row,) = convergence_rows([run])
            by_K.setdefault(K, {"K": K, "n": run.n, "N": run.N})
            by_K[K].update({f"E_max_{scheme}": row["E_max"], f"E_max_{scheme}_ci": row["E_max_ci"],
                            f"E_expected_{scheme}": row["E_max_expected"]})
    rows = [by_K[K] for K in sorted(by_K)]
    for scheme in ("euler", "strang"):
        if any(f"E_max_{scheme}" not in row for row in rows):
            raise ValueError(f"Table 2 needs an Euler and a Strang run for every K; {scheme} is missing one")
        _cf(rows, f"E_max_{scheme}", f"CF_{scheme}")
    return rows


def fit_order(x, y):
    """Order of convergence p of y = C x^-p: minus the least-squares slope of ln y against ln x
    (scipy linregress), with its standard error (nan for two points)."""
    from scipy import stats

    x, y = np.asarray(x, float), np.asarray(y, float)
    ok = (x > 0) & (y > 0)
    if ok.sum() < 2:
        return float("nan"), float("nan")
    fit = stats.linregress(np.log(x[ok]), np.log(y[ok]))
    return float(-fit.slope), float(fit.stderr) if ok.sum() > 2 else float("nan")


# ----------------------------------------------------------------------------- RW05 Tables 3-6
STEADY_COLUMNS = {  # the paper's columns, then ours
    "steps": ["K", "T_inf", "Error", "CF_Error", "Conf", "CPU", "CF_CPU",
              "n", "dt", "T_scheme", "T_expected", "T_inf_centred", "samples", "wall_seconds"],
    "single": ["T_inf", "Error", "Conf", "CPU", "n", "T_scheme", "T_expected", "T_inf_centred", "samples",
               "wall_seconds"],
    "methods": ["method", "T_inf", "Error", "Conf", "K", "n", "T_exact", "Error_percent", "T_scheme",
                "T_expected", "T_inf_centred", "CPU", "wall_seconds"],
}


def steady_rows(steadies, nosplit, dt_unit):
    """RW05 Tables 3-6: one row per steady run (dicts of read_steady). T_inf: the average of the
    uncentred temperature over t_m > s0; Conf: its confidence half-width over those samples;
    Error = |T_inf - T_exact| with T_exact = 2 beta / k (eq. 25); CPU: wall_seconds of the
    simulator (/provenance) relative to the no-splitting run `nosplit`; T_scheme: the scheme's
    stationary mean as n -> infinity; T_expected: with the finite-n bias of the estimator.
    Sorted by K (splitting) with CF_Error = previous/this and CF_CPU = this/previous."""
    rows = []
    for s in steadies:
        d = s["config"]["dsmc"]
        scheme = d.get("scheme", "nosplit")
        T0, alpha, beta, gamma, C0 = _physics(d)
        dt = None if scheme == "nosplit" else d["t_end"] / d["steps"]
        T_exact = scheme_steady_temperature("nosplit", None, alpha, beta, gamma, C0)
        T_scheme = scheme_steady_temperature(scheme, dt, alpha, beta, gamma, C0)
        t_avg = s["time"][s["time"] > d["steady_from"] + 1e-12]
        rows.append({
            "method": scheme, "K": None if dt is None else int(round(dt_unit / dt)), "n": s["n"], "dt": dt,
            "T_inf": s["mean"], "Conf": s["ci"], "Error": abs(s["mean"] - T_exact), "T_exact": T_exact,
            "Error_percent": 100 * abs(s["mean"] - T_exact) / T_exact, "T_scheme": T_scheme,
            "T_expected": float(np.mean(uncentred_expectation(T_scheme, t_avg, T0, beta, s["n"]))),
            "T_inf_centred": s["mean_centred"], "samples": int(t_avg.size * s["N"]),
            "wall_seconds": s["wall_seconds"], "CPU": s["wall_seconds"] / nosplit["wall_seconds"],
        })
    rows.sort(key=lambda r: (r["K"] is None, r["K"] or 0))
    _cf(rows, "Error", "CF_Error")
    for prev, row in zip([None] + rows[:-1], rows):
        row["CF_CPU"] = None if prev is None else row["CPU"] / prev["CPU"]
    return rows


REPLICA_COLUMNS = ["scheme", "K", "replicas", "T_inf_mean", "T_inf_sd", "T_inf_se", "sigma_nominal", "sd_ratio",
                   "T_expected", "z_expected", "rho1"]


def replica_rows(groups, dt_unit):
    """Our check of the steady-state confidence intervals (RW05 §4.2): for each group of
    repeated steady runs (same scheme, other seeds), the mean and the sample standard deviation
    of their T_inf, against the nominal sigma = Conf / lambda_p of one run (which takes the M
    observations as independent); sd_ratio = T_inf_sd / sigma_nominal; z_expected = (mean -
    T_expected) / (sd / sqrt(R)); rho1: mean lag-1 autocorrelation of the observations."""
    rows = []
    for steadies in groups:
        base = steady_rows(steadies, steadies[0], dt_unit)  # sorted by K: all the same scheme
        T = np.array([s["mean"] for s in steadies])
        sd = float(np.std(T, ddof=1))
        sigma = float(np.mean([s["ci"] for s in steadies])) / LAMBDA_P
        rho = []
        for s in steadies:
            x = s["series"][s["time"] > s["config"]["dsmc"]["steady_from"] + 1e-12]
            rho.append(float(np.corrcoef(x[:-1], x[1:])[0, 1]))
        rows.append({"scheme": base[0]["method"], "K": base[0]["K"], "replicas": len(steadies),
                     "T_inf_mean": float(T.mean()), "T_inf_sd": sd, "T_inf_se": sd / math.sqrt(len(T)),
                     "sigma_nominal": sigma, "sd_ratio": sd / sigma, "T_expected": base[0]["T_expected"],
                     "z_expected": (float(T.mean()) - base[0]["T_expected"]) / (sd / math.sqrt(len(T))),
                     "rho1": float(np.mean(rho))})
    return rows


# ----------------------------------------------------------------------------- RW05 §4.2 effort
EFFORT_COLUMNS = [
    "scheme", "K", "dt", "n", "s_M", "M", "observations", "N_coll_model", "N_coll", "fictitious",
    "N_kick_model", "N_kick_model_grid", "N_kick", "kick_ratio", "effort_model", "effort",
    "effort_rel_model", "effort_rel", "CPU", "wall_seconds",
]


def effort_rows(steadies, dt_unit, steady_from):
    """RW05 §4.2 effort model against the counted events (mean per ensemble) of steady runs.

    N_coll_model = pi_hat s_M with pi_hat = 2 pi gamma C0 (n - 1) (GRW05 step 2.1; RW05 eq. 20:
    2(n - 1) for C0 = 1/pi); N_kick_model = 2 N_coll + n M (no-splitting, M = observations
    averaged after s0, as printed) or s_M n / dt (splitting); N_kick_model_grid counts the kicks
    at all our observation times t_m > 0 instead of M; N_coll counts real and fictitious events.
    effort = N_coll + N_kick; *_rel: relative to the no-splitting row; CPU: wall_seconds ratio.
    """
    rows = []
    for s in steadies:
        d = s["config"]["dsmc"]
        scheme, n, s_M = d.get("scheme", "nosplit"), s["n"], d["t_end"]
        dt = None if scheme == "nosplit" else d["t_end"] / d["steps"]
        M = int(np.sum(s["time"] > steady_from + 1e-12))
        obs = int(np.sum(s["time"] > 1e-12))
        n_coll_model = 2 * math.pi * d.get("gamma", 1.0) * d["kernel"]["C"] * (n - 1) * s_M
        if d["kernel"]["lambda"] != 0:
            raise ValueError("the effort model of RW05 §4.2 needs lambda = 0 (no fictitious collisions)")
        kick = (2 * n_coll_model + n * M, 2 * n_coll_model + n * obs) if dt is None else (s_M * n / dt,) * 2
        n_coll = float(np.mean(s["events_collisions"] + s["events_fictitious"]))
        n_kick = float(np.mean(s["events_kicks"]))
        rows.append({
            "scheme": scheme, "K": None if dt is None else int(round(dt_unit / dt)), "dt": dt, "n": n,
            "s_M": s_M, "M": M, "observations": obs, "N_coll_model": round(n_coll_model), "N_coll": round(n_coll),
            "fictitious": round(float(np.mean(s["events_fictitious"]))), "N_kick_model": round(kick[0]),
            "N_kick_model_grid": round(kick[1]), "N_kick": round(n_kick), "kick_ratio": n_kick / kick[1],
            "effort_model": round(n_coll_model + kick[1]), "effort": round(n_coll + n_kick),
            "wall_seconds": s["wall_seconds"],
        })
    ref = [r for r in rows if r["scheme"] == "nosplit"]
    if len(ref) != 1:
        raise ValueError("the effort table needs exactly one no-splitting run")
    for row in rows:
        row["effort_rel_model"] = row["effort_model"] / ref[0]["effort_model"]
        row["effort_rel"] = row["effort"] / ref[0]["effort"]
        row["CPU"] = row["wall_seconds"] / ref[0]["wall_seconds"]
    order = {"nosplit": 0, "euler": 1, "strang": 2}
    return sorted(rows, key=lambda r: (order[r["scheme"]], r["K"] or 0))


# ----------------------------------------------------------------------------- GRW05 §5.3 tails
def kernel_name(lam):
    """The kernel's name in the published tail table."""
    return {0.0: "maxwell", 1.0: "hard_spheres"}.get(float(lam), "vhs")


def tail_points(hist, k0, min_count, histogram="density", row=-1):
    """(k, x_k, y_k) of GRW05 eq. (38) from the histogram at observation `row` (default: last).

    Shells are 1-based as in the paper (f_1: |v| < r_1); x_k = ln(k - k0) (the shell index: the
    same slope as ln(r_k - r_k0), since r_k = k h), y_k = ln(ln f_k0 - ln f_k), k > k0.
    histogram = "density": f_k is the fraction of eq. (37) divided by the shell volume
    4 pi (r_k^3 - r_{k-1}^3) / 3, an estimate of f_inf(r_k) as eq. (38) models it; "fraction":
    the fraction itself (then y_k is undefined wherever f_k >= f_k0, i.e. below the shell where
    the r^2-weighted fraction falls under f_k0). Skipped: the overflow shell, shells with fewer
    than min_count particles (over all ensembles) and shells with f_k >= f_k0.
    """
    f, counts = hist["mean"][row, :-1], hist["counts"][row, :-1]
    if histogram == "density":
        edges = hist["edges"]
        f = f / (4.0 * math.pi / 3.0 * (edges[1:] ** 3 - edges[:-1] ** 3))
    elif histogram != "fraction":
        raise ValueError(f"histogram must be density or fraction, not {histogram!r}")
    if counts[k0 - 1] < min_count or f[k0 - 1] <= 0:
        raise ValueError(f"reference shell k0 = {k0} is empty")
    k = np.arange(1, f.size + 1)
    keep = (k > k0) & (counts >= min_count) & (f > 0) & (f < f[k0 - 1])
    return k[keep], np.log(k[keep] - k0), np.log(np.log(f[k0 - 1]) - np.log(f[keep]))


def fit_tail(x, y, window):
    """Least-squares line y = c + b x on window[0] <= x <= window[1] (scipy linregress): dict
    b, b_stderr, intercept, points (nan with fewer than 3 points)."""
    from scipy import stats

    x, y = np.asarray(x, float), np.asarray(y, float)
    sel = (x >= window[0]) & (x <= window[1])
    if sel.sum() < 3:
        return {"b": float("nan"), "b_stderr": float("nan"), "intercept": float("nan"), "points": int(sel.sum())}
    fit = stats.linregress(x[sel], y[sel])
    return {"b": float(fit.slope), "b_stderr": float(fit.stderr), "intercept": float(fit.intercept),
            "points": int(sel.sum())}


TAIL_COLUMNS = ["example", "kernel", "lambda", "theory_b", "b", "b_stderr", "fit_window",
                "x_variable", "histogram", "k0", "points", "intercept", "R", "t_end", "n", "N"]
WINDOW_COLUMNS = ["example", "lambda", "histogram", "window", "k_minus_k0", "points", "b", "b_stderr", "theory_b"]


def window_text(window):
    return f"[{window[0]:g}, {window[1]:g}]"


def tail_rows(hists, tails):
    """The tail-exponent table (one row per example: the fit on tails["fit_window"] with
    tails["histogram"]) and the window table (every example on every window of tails["windows"],
    for both histogram normalisations). hists: {example number: read_histogram dict}; theory_b =
    1 + lambda/2 (GRW05 eqs. 20, 21)."""
    rows, wrows = [], []
    for ex, hist in sorted(hists.items()):
        d = hist["config"]["dsmc"]
        lam = float(d["kernel"]["lambda"])
        _, x, y = tail_points(hist, tails["k0"], tails["min_count"], tails["histogram"])
        fit = fit_tail(x, y, tails["fit_window"])
        rows.append({"example": ex, "kernel": kernel_name(lam), "lambda": lam, "theory_b": 1 + lam / 2,
                     "fit_window": window_text(tails["fit_window"]), "x_variable": "ln(k-k0)",
                     "histogram": tails["histogram"], "k0": tails["k0"], "R": d["histogram"]["radius"],
                     "t_end": d["t_end"], "n": hist["n"], "N": hist["N"], **fit})
        for histogram in ("density", "fraction"):
            _, x, y = tail_points(hist, tails["k0"], tails["min_count"], histogram)
            for w in tails["windows"]:
                lo, hi = math.ceil(math.exp(w[0]) - 1e-9), math.floor(math.exp(w[1]) + 1e-9)
                wrows.append({"example": ex, "lambda": lam, "histogram": histogram, "window": window_text(w),
                              "k_minus_k0": f"{lo}-{hi}", "theory_b": 1 + lam / 2, **fit_tail(x, y, w)})
    return rows, wrows


# ----------------------------------------------------------------------------- figures
def pyplot():
    """matplotlib.pyplot on the Agg backend with the house style (a printed paper's look)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    plt.rcParams.update(
        {
            "font.family": "serif",
            "font.serif": ["DejaVu Serif"],
            "mathtext.fontset": "dejavuserif",
            "font.size": 9,
            "axes.labelsize": 9,
            "axes.titlesize": 9,
            "axes.linewidth": 0.6,
            "legend.fontsize": 8,
            "legend.frameon": False,
            "lines.linewidth": 0.8,
            "xtick.direction": "in",
            "ytick.direction": "in",
            "xtick.top": True,
            "ytick.right": True,
            "xtick.major.width": 0.6,
            "ytick.major.width": 0.6,
            "savefig.dpi": 200,
            "savefig.bbox": "tight",
            "savefig.pad_inches": 0.02,
        }
    )
    return plt


def save_figure(fig, paths):
    """Save `fig` to each path (format from the extension), each atomically; PDFs carry no
    creation date, so a rerun gives the same bytes."""
    for path in paths:
        fmt = os.path.splitext(path)[1][1:]
        metadata = {"CreationDate": None} if fmt == "pdf" else None
        with atomic_path(path) as tmp:
            fig.savefig(tmp, format=fmt, metadata=metadata)


def figure_summary(ours, short, **numbers):
    """The JSON summary a figure rule writes next to its figure: the one-line description of
    what our figure shows (`ours`, computed from the numbers), a shorter one for the report's
    summary table (`short`) and the numbers themselves."""
    return {"ours": ours, "short": short, "numbers": numbers}
