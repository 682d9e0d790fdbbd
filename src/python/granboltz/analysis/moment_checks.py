"""Simulated speed moments against the exact Maxwell hierarchy.

GRW05 Example 7 (lambda = 0): M_2p = <|v - V|^2p>, p = 1..P, of the final state (the simulator's
/moment_2p, docs/output.md) against the exact time-dependent value at t_end (and the steady one)
of granboltz.theory.maxwell_hierarchy.  RW05 §4 (Fig. 3): <|v - V|^4>(t) and Crit(t) against the exact
curves.  The tail amplitude a of Ex. 7 from the growth of the exact moments (tail_theory).
Confidence half-widths are Z = 3.2 standard errors (GRW05 §5.1); sigma = (ours - exact) / se.
"""
import math
from fractions import Fraction
from math import pi, sqrt

import numpy as np

from ..theory import maxwell_hierarchy as mh
from ..theory.dimension import check_dimension, check_maxwellian_start
from ..output.io import open_run, read_config, read_finite
from ..theory import LAMBDA_P
from ..theory.tail_theory import amplitude_and_chi_from_moments, amplitude_from_moments, tail_amplitude

Z = LAMBDA_P
MOMENT_COLUMNS = ["p", "exact", "ours", "ci", "sigma", "exact_steady"]
AMPLITUDE_COLUMNS = ["p", "ratio", "a_chi0", "a", "chi", "a_theory"]
RW05_COLUMNS = ["n", "N", "t", "M4", "M4_ci", "M4_exact", "M4_sigma", "crit", "crit_ci", "crit_exact",
                "crit_sigma"]


def hierarchy_physics(config):
    """(alpha, beta, nu, T0) of a run config (its dsmc section) as Fractions for the hierarchy;
    nu = 4 pi C0 gamma with pi*C0 recovered as a simple fraction (1/4 for C0 = 1/(4 pi)).
    ValueError for lambda != 0 or d != 3 (the hierarchy's)."""
    d = config["dsmc"]
    if float(d["kernel"]["lambda"]) != 0.0:
        raise ValueError(f"the exact hierarchy needs lambda = 0, not {d['kernel']['lambda']}")
    check_maxwellian_start(d, "the exact hierarchy")
    pi_c = Fraction(float(d["kernel"]["C"]) * pi).limit_denominator(1000)
    frac = [Fraction(str(d[k])) for k in ("alpha", "beta")]
    T0 = Fraction(str(d.get("initial", {}).get("temperature", 1.0)))
    return frac[0], frac[1], mh.collision_rate(Fraction(str(d["gamma"])), pi_c, int(d.get("dimension", 3))), T0


def read_speed_moments(path, row=-1):
    """(config, t, means [P], cis [P]) of /moment_2, ..., /moment_2P at observation `row`."""
    with open_run(path) as f:
        config = read_config(f, path)
        P = int(config["dsmc"].get("moments", 4))
        mean = [float(read_finite(f, f"moment_{2 * p}/mean", path)[row]) for p in range(1, P + 1)]
        ci = [float(read_finite(f, f"moment_{2 * p}/ci", path)[row]) for p in range(1, P + 1)]
        return config, float(read_finite(f, "time", path)[row]), np.array(mean), np.array(ci)


def moment_rows(means, cis, alpha, beta, nu, T0, t, d=3):
    """Rows p, exact (M_2p at time t from a Maxwellian of temperature T0), ours, ci, sigma,
    exact_steady for p = 1..len(means) (d = 3: the hierarchy's)."""
    P = len(means)
    timed = mh.time_dependent_moments(P, alpha, beta, nu, T0, d)
    steady = mh.steady_moments(P, alpha, beta, nu, d)
    rows = []
    for p in range(1, P + 1):
        exact = float(mh.evaluate(timed[p], [t])[0])
        se = cis[p - 1] / Z
        rows.append({"p": p, "exact": exact, "ours": float(means[p - 1]), "ci": float(cis[p - 1]),
                     "sigma": (means[p - 1] - exact) / se if se > 0 else float("nan"),
                     "exact_steady": float(steady[p])})
    return rows


def moment_verdict(rows):
    """Short verdict: 'agrees' if every |ours - exact| <= ci, else 'differs' (with the rows that
    do not, and the largest relative deviation of the exact value from the steady one)."""
    out = [r for r in rows if not abs(r["ours"] - r["exact"]) <= r["ci"]]
    zmax = max(abs(r["sigma"]) for r in rows)
    relax = max(abs(r["exact"] / r["exact_steady"] - 1) for r in rows)
    names = f"M_2…M_{2 * int(rows[-1]['p'])}"
    tail = f"(max |σ| = {zmax:.1f}; exact at t_end vs steady: ≤ {relax:.1e} relative)"
    if not out:
        return f"agrees: {names} within their ci of the exact values {tail}"
    bad = ", ".join(f"M_{2 * int(r['p'])} ({r['sigma']:+.1f}σ)" for r in out)
    return f"differs: {len(out)} of {len(rows)} moments outside their ci: {bad} {tail}"


def amplitude_rows(alpha, beta, nu, pmax=40, lam=0.0, d=3):
    """The tail amplitude of the exact steady moments M_0..M_2pmax (lambda = 0, d = 3): rows p = 0..pmax-2, ratio
    M_{2p+2}/M_2p, a_chi0 (chi = 0), a and chi (from two successive ratios), a_theory = sqrt(nu/beta)."""
    M = mh.steady_moments(pmax, alpha, beta, nu, d)
    a0 = amplitude_from_moments(M, d=d)
    a, chi = amplitude_and_chi_from_moments(M, d)
    a_th = tail_amplitude(float(nu), float(beta), lam, d)
    return [{"p": p, "ratio": float(M[p + 1] / M[p]), "a_chi0": float(a0[p]), "a": float(a[p]),
             "chi": float(chi[p]), "a_theory": a_th} for p in range(len(a))]


def rw05_moment_rows(run, times=None):
    """RW05 §4: rows of <|v - V|^4>(t) (the run's /moment_4 when present) and Crit(t) (crit_of_means)
    against the exact curves, at the observation times nearest to `times` (default: all)."""

    alpha, beta, nu, T0 = hierarchy_physics(run.config)
    exact = mh.time_dependent_moments(2, alpha, beta, nu, T0)
    idx = range(len(run.time)) if times is None else [int(np.argmin(abs(run.time - t))) for t in times]
    idx = list(idx)
    t = run.time[idx]
    M2, M4 = mh.evaluate(exact[1], t), mh.evaluate(exact[2], t)
    crit, crit_ci = crit_of_means(run)
    m4, m4_ci = run.moments.get("moment_4/mean"), run.moments.get("moment_4/ci")
    rows = []
    for j, i in enumerate(idx):
        c_exact = float(mh.crit(M2[j], M4[j]))
        row = {"n": run.n, "N": run.N, "t": float(t[j]), "M4": float(m4[i]), "M4_ci": float(m4_ci[i]),
               "M4_exact": float(M4[j]), "crit": float(crit[i]), "crit_ci": float(crit_ci[i]),
               "crit_exact": c_exact}
        row["M4_sigma"] = _sigma(row["M4"], row["M4_exact"], row["M4_ci"])
        row["crit_sigma"] = _sigma(row["crit"], c_exact, row["crit_ci"])
        rows.append({k: row[k] for k in RW05_COLUMNS})
    return rows


def _sigma(ours, exact, ci):
    return (ours - exact) / (ci / Z) if ci > 0 else float("nan")


def crit_estimator_bias(run):
    """Bias of Crit at the ensemble means from the spread of the per-ensemble temperatures:
    mean(M4_i - 15 T_i^2) = mean M4 - 15 (mean T)^2 - 15 var(T_i), so Crit is low by about
    15 var(T_i) / (sqrt(120) T^2) (var(T_i) = N se_T^2), [M+1].  d = 3 (RW05's Crit)."""
    check_dimension(int(run.dsmc.get("dimension", 3)), (3,), "crit_estimator_bias")
    var_T = run.N * (run.T_centred_ci / Z) ** 2
    return 15.0 * var_T / (sqrt(120.0) * run.T_centred**2)


def crit_verdict(rows, bias=None):
    """Short verdict of RW05 moments: does the exact Crit(t) lie inside the band at every t?"""
    out = [r for r in rows if not abs(r["crit"] - r["crit_exact"]) <= r["crit_ci"]]
    zmax = max(abs(r["crit_sigma"]) for r in rows)
    head = f"n = {rows[0]['n']}, N = {rows[0]['N']}"
    extra = "" if bias is None else f"; estimator bias ≈ −{bias:.1e}"
    if not out:
        return f"agrees: exact Crit(t) inside the {head} band at all {len(rows)} t (max |σ| = {zmax:.1f}{extra})"
    return (f"differs: {len(out)} of {len(rows)} point(s) outside the {head} band (max |σ| = {zmax:.1f}"
            f"{extra})")


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
