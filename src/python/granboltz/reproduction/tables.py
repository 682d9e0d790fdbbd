"""The numbers of GRW05 Tables 1-2 and RW05 Tables 1-2 (convergence in n and in the time step)
from DSMC runs (granboltz.reproduction.dsmc.DsmcRun), and the fitted order of convergence.

Each builder returns a list of dict rows; the *_COLUMNS lists give the CSV column order (the
paper's columns first, then ours).
"""

import numpy as np

from ..theory import expected_error, run_analytic_temperature


def cf_column(rows, key, cf):
    """CF columns: quotient of consecutive values of `key` (previous / this), None in row one."""
    for prev, row in zip([None] + rows[:-1], rows):
        row[cf] = None if prev is None or not row[key] else prev[key] / row[key]


def sorted_unique(runs, key, what="n"):
    """The runs sorted by key(run); ValueError if two share a key."""
    runs = sorted(runs, key=key)
    if len({key(r) for r in runs}) != len(runs):
        raise ValueError(f"two runs with the same {what}: " + ", ".join(r.path for r in runs))
    return runs


# ----------------------------------------------------------------------------- GRW05 Tables 1, 2
TABLE_COLUMNS = [
    *["n", "N", "E_max", "CF", "V_inf"],  # the paper's columns, and N
    *["E_max_ci", "t_Emax", "Conf_end", "E_max_expected", "E_max_centred", "CF_centred"],  # ours
]


def convergence_rows(runs):
    """Rows of GRW05 Tables 1/2 (and RW05 Table 1's E_max), one per run, sorted by n.

    E_max = max_m |T_m - T(t_m)| / T(t_m) (GRW05 eq. 35) of the uncentred estimator; CF =
    E_max of the previous row / E_max; V_inf = max_m |V(t_m)|; E_max_ci = ci / T(t) at t_Emax,
    the time of the maximal error; Conf_end = ci / T(t) at the last time; E_max_expected = the
    exact systematic part (expected_error); E_max_centred and CF_centred: the same error for the
    centred temperature (eq. 13).
    """
    rows = []
    for run in sorted_unique(runs, lambda r: r.n):
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
    cf_column(rows, "E_max", "CF")
    cf_column(rows, "E_max_centred", "CF_centred")
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
    for row, run in zip(rows, sorted_unique(runs, lambda r: r.n)):
        exact = run_analytic_temperature(run)
        row["E_end"] = float(abs(run.T[-1] - exact[-1]) / exact[-1])
        row["T_end_exact"] = float(exact[-1])
        row["E_end_expected"] = expected_error(run)[1]
        row["E_end_centred"] = float(abs(run.T_centred[-1] - exact[-1]) / exact[-1])
    for key in ("E_end", "Conf_end", "E_max"):
        cf_column(rows, key, "CF_" + key)
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
        for run in sorted_unique(runs, lambda r: r.dt, "time step"):
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
        cf_column(rows, f"E_max_{scheme}", f"CF_{scheme}")
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

