"""Shared by the workflow scripts: HDF5 reading, analytic formulas, tables, plot style, and
atomic writing of outputs.

The scripts import this module by name (Snakemake puts a script's directory on sys.path). It
never touches the `snakemake` object: every function takes plain paths and values, so the tests
call it directly.
"""

import contextlib
import csv
import math
import os
import tempfile
from dataclasses import dataclass

import h5py
import numpy as np
import yaml

# Temperature estimator behind the published error tables: phi(v) = |v|^2 / 3 (RW05 §4.1). Its
# exact finite-n bias matches the published E_max (about 5.7/n in GRW05 Example 3); the centred
# temperature (GRW05 eq. 13) is biased by only about 1/n and is reported alongside.
TEMPERATURE = "temperature_uncentred"
TEMPERATURE_CENTRED = "temperature"


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


def write_csv(rows, columns, path):
    """Write dict rows as CSV (floats with 4 significant digits, None as empty), atomically."""

    def cell(value):
        if value is None:
            return ""
        if isinstance(value, float):
            return f"{value:.4g}" if math.isfinite(value) else "nan"
        return str(value)

    with atomic_path(path) as tmp:
        with open(tmp, "w", newline="") as out:
            writer = csv.writer(out, lineterminator="\n")
            writer.writerow(columns)
            for row in rows:
                writer.writerow([cell(row[c]) for c in columns])


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


def _text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def read_run(path):
    """Read one granboltz DSMC output file into a Run; refuse non-finite values."""

    def finite(f, name):
        data = f[name][:]
        if not np.all(np.isfinite(data)):
            raise ValueError(f"{path}: dataset /{name} has non-finite values")
        return data

    with h5py.File(path, "r") as f:
        config = yaml.safe_load(_text(f.attrs["config"]))
        return Run(
            path=str(path),
            config=config,
            n=int(config["dsmc"]["particles"]),
            N=int(f.attrs["ensembles"]),
            time=finite(f, "time"),
            T=finite(f, f"{TEMPERATURE}/mean"),
            T_ci=finite(f, f"{TEMPERATURE}/ci"),
            T_centred=finite(f, f"{TEMPERATURE_CENTRED}/mean"),
            T_centred_ci=finite(f, f"{TEMPERATURE_CENTRED}/ci"),
            V=finite(f, "bulk_velocity/mean"),
        )


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


def run_analytic_temperature(run):
    """Eq. (16) with the parameters the run was made with (lambda must be 0: eq. 16 is exact
    for Maxwell pseudomolecules only)."""
    d = run.config["dsmc"]
    if d["kernel"]["lambda"] != 0:
        raise ValueError(f"{run.path}: eq. (16) needs kernel lambda = 0, got {d['kernel']['lambda']}")
    T0 = d.get("initial", {}).get("temperature", 1.0)
    return analytic_temperature(run.time, T0, d["alpha"], d["beta"], d.get("gamma", 1.0), d["kernel"]["C"])


# ----------------------------------------------------------------------------- tables
TABLE_COLUMNS = [
    *["n", "N", "E_max", "CF", "V_inf"],  # the paper's columns, and N
    *["E_max_ci", "t_Emax", "Conf_end", "E_max_centred", "CF_centred"],  # ours
]


def convergence_rows(runs):
    """Rows of GRW05 Tables 1/2 (and RW05 Table 1's E_max), one per run, sorted by n.

    E_max = max_m |T_m - T(t_m)| / T(t_m) (GRW05 eq. 35) of the uncentred estimator; CF =
    E_max of the previous row / E_max; V_inf = max_m |V(t_m)|; E_max_ci = ci / T(t) at t_Emax,
    the time of the maximal error; Conf_end = ci / T(t) at the last time; E_max_centred and
    CF_centred: the same with the centred temperature (eq. 13).
    """
    runs = sorted(runs, key=lambda r: r.n)
    if len({r.n for r in runs}) != len(runs):
        raise ValueError("two runs with the same n: " + ", ".join(r.path for r in runs))
    rows = []
    for run in runs:
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
                "E_max_centred": float(np.max(np.abs(run.T_centred - exact) / exact)),
            }
        )
    for key, cf in (("E_max", "CF"), ("E_max_centred", "CF_centred")):
        for prev, row in zip([None] + rows[:-1], rows):
            row[cf] = None if prev is None else prev[key] / row[key]
    return rows


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
