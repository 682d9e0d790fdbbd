"""The numbers of RW05 Tables 3-6 (steady state), our check of their confidence intervals with
repeated runs, and the effort model of RW05 §4.2, from the steady-state averages of runs
(granboltz.reproduction.dsmc.read_steady dicts).
"""

import math

import numpy as np

from .tables import cf_column
from ..theory.dimension import dsmc_geometry
from ..theory import LAMBDA_P, dsmc_physics, scheme_steady_temperature, uncentred_expectation


# ----------------------------------------------------------------------------- RW05 Tables 3-6
STEADY_COLUMNS = {  # the paper's columns, then ours, first the honest interval of Conf's run
    "steps": ["K", "T_inf", "Error", "CF_Error", "Conf", "CPU", "CF_CPU", "Conf_batch", "tau_int",
              "n", "dt", "T_scheme", "T_expected", "T_inf_centred", "samples", "wall_seconds"],
    "single": ["T_inf", "Error", "Conf", "CPU", "Conf_batch", "tau_int", "n", "T_scheme", "T_expected",
               "T_inf_centred", "samples", "wall_seconds"],
    "methods": ["method", "T_inf", "Error", "Conf", "Conf_batch", "tau_int", "K", "n", "T_exact", "Error_percent",
                "T_scheme", "T_expected", "T_inf_centred", "CPU", "wall_seconds"],
}


def steady_rows(steadies, nosplit, dt_unit):
    """RW05 Tables 3-6: one row per steady run (dicts of read_steady). T_inf: the average of the
    uncentred temperature over t_m > s0; Conf: its confidence half-width over those samples,
    taken as independent (the papers' method, steady_ci: independent); Conf_batch: the batch
    estimator's half-width of the same run, which accounts for their correlation, and tau_int
    the integrated autocorrelation time in observations it measured (None without);
    Error = |T_inf - T_exact| with T_exact = 2 beta / k (eq. 25); CPU: wall_seconds of the
    simulator (/provenance) relative to the no-splitting run `nosplit`; T_scheme: the scheme's
    stationary mean as n -> infinity; T_expected: with the finite-n bias of the estimator.
    Sorted by K (splitting) with CF_Error = previous/this and CF_CPU = this/previous."""
    rows = []
    for s in steadies:
        d = s["config"]["dsmc"]
        scheme = d.get("scheme", "nosplit")
        T0, alpha, beta, gamma, C0 = dsmc_physics(d)
        dt = None if scheme == "nosplit" else d["t_end"] / d["steps"]
        dim, geometry = dsmc_geometry(d)
        T_exact = scheme_steady_temperature("nosplit", None, alpha, beta, gamma, C0, dim, geometry)
        T_scheme = scheme_steady_temperature(scheme, dt, alpha, beta, gamma, C0, dim, geometry)
        t_avg = s["time"][s["time"] > d["steady_from"] + 1e-12]
        rows.append({
            "method": scheme, "K": None if dt is None else int(round(dt_unit / dt)), "n": s["n"], "dt": dt,
            "T_inf": s["mean"], "Conf": s["ci"], "Conf_batch": s.get("ci_batch"),
            "tau_int": s.get("tau_int_batch"), "Error": abs(s["mean"] - T_exact), "T_exact": T_exact,
            "Error_percent": 100 * abs(s["mean"] - T_exact) / T_exact, "T_scheme": T_scheme,
            "T_expected": float(np.mean(uncentred_expectation(T_scheme, t_avg, T0, beta, s["n"], dim))),
            "T_inf_centred": s["mean_centred"], "samples": int(t_avg.size * s["N"]),
            "wall_seconds": s["wall_seconds"], "CPU": s["wall_seconds"] / nosplit["wall_seconds"],
        })
    rows.sort(key=lambda r: (r["K"] is None, r["K"] or 0))
    cf_column(rows, "Error", "CF_Error")
    for prev, row in zip([None] + rows[:-1], rows):
        row["CF_CPU"] = None if prev is None else row["CPU"] / prev["CPU"]
    return rows


REPLICA_COLUMNS = ["scheme", "K", "replicas", "T_inf_mean", "T_inf_sd", "T_inf_se", "sigma_nominal", "sd_ratio",
                   "sigma_batch", "sd_ratio_batch", "T_expected", "z_expected", "rho1"]


def replica_rows(groups, dt_unit):
    """Our check of the steady-state confidence intervals (RW05 §4.2): for each group of
    repeated steady runs (same scheme, other seeds), the mean and the sample standard deviation
    of their T_inf, against the nominal sigma = Conf / lambda_p of one run (which takes the M
    observations as independent); sd_ratio = T_inf_sd / sigma_nominal; sigma_batch: the batch
    estimator's sigma of one run (root mean square over the runs, since each estimates a variance;
    None without), sd_ratio_batch = T_inf_sd / sigma_batch; z_expected = (mean - T_expected) /
    (sd / sqrt(R)); rho1: mean lag-1 autocorrelation of the observations."""
    rows = []
    for steadies in groups:
        base = steady_rows(steadies, steadies[0], dt_unit)  # sorted by K: all the same scheme
        T = np.array([s["mean"] for s in steadies])
        sd = float(np.std(T, ddof=1))
        sigma = float(np.mean([s["ci"] for s in steadies])) / LAMBDA_P
        batch = [s.get("sigma_batch") for s in steadies]
        sigma_batch = None if None in batch else float(np.sqrt(np.mean(np.square(batch))))
        rho = []
        for s in steadies:
            x = s["series"][s["time"] > s["config"]["dsmc"]["steady_from"] + 1e-12]
            rho.append(float(np.corrcoef(x[:-1], x[1:])[0, 1]))
        rows.append({"scheme": base[0]["method"], "K": base[0]["K"], "replicas": len(steadies),
                     "T_inf_mean": float(T.mean()), "T_inf_sd": sd, "T_inf_se": sd / math.sqrt(len(T)),
                     "sigma_nominal": sigma, "sd_ratio": sd / sigma, "sigma_batch": sigma_batch,
                     "sd_ratio_batch": None if sigma_batch is None else sd / sigma_batch,
                     "T_expected": base[0]["T_expected"],
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

