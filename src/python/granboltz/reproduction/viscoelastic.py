"""Free cooling of viscoelastic hard spheres, d = 3 (Beyond the papers; the theory functions take d
and raise ValueError for another, granboltz.theory.dimension): the restitution law of the
simulator's `dsmc.restitution: {law: viscoelastic, delta: δ}`, the cooling law T(t) ~ t^(-5/3)
(Brilliantov & Pöschel), and the table rows and verdict of the report item.

Law (Schwager & Pöschel 1998; docs/config.md, Restitution laws): ε = 1 − C1 x + C2 x², x = δ g_n^(1/5),
held at 7/12 for x ≥ X_HOLD = 5/(6 C1).  Units as granboltz.reproduction.beyond: density 1, kernel B = C|u|, collision
term γQ.  The Maxwellian moment equation is

    dT/dt = −ζ(T) T,  ζ(T) = (16/3)√π γC (n − 1)/n √T Φ(T),  Φ(T) = ⟨|u| g_n² (1 − ε²)⟩/⟨|u| g_n²⟩,

the simulator's `estimate` with 1 − α² replaced by Φ [approx: a2 = 0].  To leading order Φ = A1 δ T^(1/10),
so dT/dt ∝ −δ T^(8/5) and T = T0 [1 + (3/5) t/τ0]^(−5/3) with τ0 = 1/ζ(T0) (reference/beyond.md §6),
not Haff's t^(−2).  The local slope d ln T/d ln t tends to −5/3 only slowly: to first order

    s(t) = −(5/3) [1 − 5τ0/(3t) + (B1/5) δ T(t)^(1/10)],   B1 = A2/A1 = 1.53,

the offset τ0 and the x² term of ε, which decays like t^(−1/6) (late_slope_expansion; the tests check it
against the moment equation).  free_cooling_temperature solves the moment equation with the full law.
"""

import math

import numpy as np

from .beyond import Z
from ..theory.dimension import check_dimension, initial_temperature
from ..theory.sonine import cooling_rate

C1 = math.gamma(0.6) * math.sqrt(math.pi) / (2**0.2 * 5**0.4 * math.gamma(2.1))  # 1.1534489
C2 = 0.6 * C1**2
X_HOLD, EPS_HOLD = 5 / (6 * C1), 7 / 12  # the two-term series' minimum: ε is held there
# 1 − ε(x)² = Σ_k LOSS[k] x^k (k = 1…4) below the hold
LOSS = (0.0, 2 * C1, -(C1**2 + 2 * C2), 2 * C1 * C2, -(C2**2))


def _moment(k):
    """⟨(4 s z)^(k/10)⟩ over the pair weight |u| g_n² of a Maxwellian at T = 1: s = u²/4 ~ Gamma(3), z = (û·n)²
    with density 2z, so that x = δ (4 T s z)^(1/10)."""
    return 4 ** (k / 10) * math.gamma(3 + k / 10) / 2 * 2 / (2 + k / 10)


A1 = LOSS[1] * _moment(1)  # Φ = A1 δ T^(1/10) − A2 δ² T^(1/5) + …: A1 = 2.7731
A2 = -LOSS[2] * _moment(2)
B1 = A2 / A1
# First-Sonine factor of ⟨|u|^p⟩, p(p − 2)/16 (granboltz.theory.sonine.cooling_rate), at the loss term's p = 16/5
P_LOSS = 3.2  # the loss term's moment order p = 16/5 (not lambda_p)
KAPPA = P_LOSS * 1.2 / 16
# δ = 0 conserves energy to rounding: even 10^6 collisions per ensemble, each rounding the same way, drift
# by only 10^6 × 2^−52 ≈ 2e-10, while any real loss is of order δ
ELASTIC_TOL = 1e-9


def restitution(x):
    """ε(x), x = δ g_n^(1/5): 1 − C1 x + C2 x², held at 7/12 for x ≥ X_HOLD (as the simulator)."""
    x = np.asarray(x, dtype=float)
    return np.where(x >= X_HOLD, EPS_HOLD, 1 - x * (C1 - C2 * x))


def loss_fraction(T, delta, d=3):
    """Φ(T) = ⟨|u| g_n² (1 − ε²)⟩/⟨|u| g_n²⟩ for a Maxwellian at temperature T (the factor that replaces
    1 − α² in the cooling rate): the series in closed form, plus the correction where x ≥ X_HOLD (incomplete
    gamma functions, Gauss-Legendre in z; nil unless δ (g_n)^(1/5) reaches 0.72 in the thermal range).
    d = 3 only (the pair weight |u| g_n² of spheres)."""
    from scipy.special import gammaincc

    check_dimension(d, (3,), "viscoelastic.loss_fraction")
    if delta == 0:
        return 0.0
    scale = [(delta * T**0.1) ** k for k in range(5)]  # x^k = scale[k] (4 s z)^(k/10)
    phi = sum(LOSS[k] * scale[k] * _moment(k) for k in range(1, 5))
    q = (X_HOLD / delta) ** 10 / (4 * T)  # x >= X_HOLD where s z >= q
    if q > 700:  # the weight beyond it is below e^-700
        return float(phi)
    zg, wg = np.polynomial.legendre.leggauss(64)
    z, w = (zg + 1) / 2, wg / 2
    # where held, 1 - eps_hold^2 = (1 - eps^2) + (eps^2 - eps_hold^2), eps^2 - eps_hold^2 = sum excess[k] x^k
    excess = (1.0 - EPS_HOLD**2, -2 * C1, C1**2 + 2 * C2, -2 * C1 * C2, C2**2)
    tail = sum(excess[k] * scale[k] * 4 ** (k / 10) * math.gamma(3 + k / 10) / 2
               * np.sum(w * 2 * z ** (1 + k / 10) * gammaincc(3 + k / 10, q / z)) for k in range(5))
    return float(phi + tail)


def cooling_rate_visco(T, delta, gamma, C, n=None, d=3):
    """ζ(T) of the Maxwellian moment equation dT/dt = −ζ T: the hard-sphere rate with 1 − α² → Φ(T) (d = 3)."""
    return float(cooling_rate(T, 0.0, gamma, C, 1, n=n, d=d)) * loss_fraction(T, delta, d)


def tau0(delta, T0, gamma, C, n=None, d=3):
    """τ0 = 1/ζ(T0) to leading order in δ (ζ = (16/3)√π γC √T0 A1 δ T0^(1/10)); ∞ for δ = 0 (d = 3)."""
    check_dimension(d, (3,), "viscoelastic.tau0")
    zeta0 = float(cooling_rate(T0, 0.0, gamma, C, 1, n=n)) * A1 * delta * T0**0.1
    return math.inf if zeta0 == 0 else 1 / zeta0


def asymptotic_temperature(t, delta, T0, gamma, C, n=None, d=3):
    """T0 [1 + (3/5) t/τ0]^(−5/3), the leading order in δ [approx; exponent exact as δ T^(1/10) → 0] (d = 3)."""
    return T0 * (1 + 0.6 * np.asarray(t, dtype=float) / tau0(delta, T0, gamma, C, n, d)) ** (-5 / 3)


def free_cooling_temperature(t, delta, T0, gamma, C, n=None, d=3):
    """T(t) of the Maxwellian moment equation with the full law (DOP853 in ln T, relative tolerance 1e-11),
    at the times t (≥ 0) [approx: with a steady a2, the true T is about this T times (1 + KAPPA a2)^(−5/3) late]
    (d = 3)."""
    from scipy.integrate import solve_ivp

    check_dimension(d, (3,), "viscoelastic.free_cooling_temperature")
    t = np.asarray(t, dtype=float)
    if delta == 0 or t.max() == 0:
        return np.full(t.shape, float(T0))
    sol = solve_ivp(lambda _, y: [-cooling_rate_visco(math.exp(y[0]), delta, gamma, C, n)], (0.0, float(t.max())),
                    [math.log(T0)], method="DOP853", rtol=1e-11, atol=1e-12, dense_output=True)
    return np.exp(sol.sol(t)[0])


def local_slope(t, T, delta, gamma, C, n=None, d=3):
    """d ln T/d ln t = −t ζ(T) of the moment equation at (t, T(t)) (d = 3)."""
    check_dimension(d, (3,), "viscoelastic.local_slope")
    return np.array([-ti * cooling_rate_visco(Ti, delta, gamma, C, n, d) for ti, Ti in zip(np.atleast_1d(t), np.atleast_1d(T))])


def late_slope_expansion(t, T, delta, tau, d=3):
    """First-order local slope −(5/3)[1 − 5τ0/(3t) + (B1/5) δ T^(1/10)] for t ≫ τ0 (module docstring; d = 3)."""
    check_dimension(d, (3,), "viscoelastic.late_slope_expansion")
    t, T = np.asarray(t, dtype=float), np.asarray(T, dtype=float)
    return -5 / 3 * (1 - 5 * tau / (3 * t) + B1 / 5 * delta * T**0.1)


# ----------------------------------------------------------------------------- rows
def run_delta(run):
    """δ of a run with the viscoelastic law (dsmc.restitution); ValueError naming the file otherwise."""
    law = run.config["dsmc"].get("restitution")
    if not law or law.get("law") != "viscoelastic":
        raise ValueError(f"{run.path}: not a viscoelastic run (dsmc.restitution = {law})")
    return float(law["delta"])


def log_spaced(M, count):
    """At most `count` observation indices 1…M, about evenly spaced in ln t (the grid is uniform in t)."""
    return np.unique(np.round(np.geomspace(1, M, count)).astype(int)) if M >= 1 else np.array([], int)


def viscoelastic_rows(runs, rows, late_from):
    """One row per (δ, observation time) at `rows` log-spaced times of each free-cooling run (read_run
    objects, any order): T with its half-width, the theory (the moment equation from T0 (1 − 1/n), the
    centred estimator's mean; for δ = 0 the run's own T(0), which elastic collisions conserve in every
    ensemble), T/theory − 1, the local slope from the previous row with its half-width and the theory's,
    a2, and `late` = 1 for the times t ≥ late_from of the slope fit (δ > 0)."""
    out = []
    for run in sorted(runs, key=run_delta):
        d, delta = run.config["dsmc"], run_delta(run)
        n, T0, g, C = int(d["particles"]), float(initial_temperature(d)), float(d["gamma"]), float(d["kernel"]["C"])
        dim = int(d.get("dimension", 3))
        idx = log_spaced(len(run.time) - 1, rows)
        t, T, ci = run.time[idx], run.temperature.mean[idx], run.temperature.ci[idx]
        th = (np.full(t.shape, run.temperature.mean[0]) if delta == 0
              else free_cooling_temperature(t, delta, T0 * (1 - 1 / n), g, C, n, dim))
        tau = tau0(delta, T0, g, C, n, dim)
        for k in range(len(idx)):
            row = {"delta": delta, "n": n, "N": int(run.config["ensembles"]), "t": float(t[k]),
                   "t_over_tau0": float(t[k] / tau), "T": float(T[k]), "ci": float(ci[k]), "T_theory": float(th[k]),
                   "rel_theory": float(T[k] / th[k] - 1), "slope": None, "slope_ci": None, "slope_theory": None,
                   "a2": float(run.a2.mean[idx[k]]), "a2_ci": float(run.a2.ci[idx[k]]),
                   "late": int(delta > 0 and t[k] >= late_from * (1 - 1e-12))}
            if k:
                span = math.log(t[k] / t[k - 1])
                row["slope"] = float(math.log(T[k] / T[k - 1]) / span)
                # any correlation between the two times: the half-widths add (triangle inequality)
                row["slope_ci"] = float((ci[k] / T[k] + ci[k - 1] / T[k - 1]) / span)
                row["slope_theory"] = float(math.log(th[k] / th[k - 1]) / span)
            out.append(row)
    return out


# ----------------------------------------------------------------------------- late slope, verdicts
def late_slope(rows):
    """Fit of ln T against ln t over the late rows of one δ, weighted by 1/(ci/T)²: the slope Σ c_i ln T_i,
    its half-width Σ|c_i| ci_i/T_i (valid whatever the correlation between the times, which the output does
    not give: the observations of one run share their ensembles), and the same fit of the theory."""
    late = [r for r in rows if r["late"]]
    if len(late) < 3:
        raise ValueError(f"δ = {rows[0]['delta'] if rows else '?'}: fewer than 3 late rows (late_from too close to t_end)")
    x = np.log([r["t"] for r in late])
    rel = np.array([r["ci"] / r["T"] for r in late])
    w = 1 / (rel / Z) ** 2
    xm = np.sum(w * x) / np.sum(w)
    c = w * (x - xm) / np.sum(w * (x - xm) ** 2)
    return {"value": float(c @ np.log([r["T"] for r in late])), "ci": float(np.abs(c) @ rel),
            "theory": float(c @ np.log([r["T_theory"] for r in late])), "t_min": late[0]["t"],
            "t_max": late[-1]["t"], "times": len(late)}


def slope_verdict(rows):
    """(ok, numbers, text) for the rows of one δ > 0.  The late slope s agrees with −5/3 when
    |s + 5/3| ≤ ci + allowance, allowance = approach + sonine: approach = |s_M + 5/3| with s_M the same fit
    of the moment equation (finite t/τ0 and the x² term of ε, module docstring); sonine = (5/3) KAPPA
    range(a2), the first-Sonine bound on what the Maxwellian theory leaves out (the cooling rate gains
    1 + KAPPA a2, which changes the late slope by −(5/3) KAPPA (a2(t) − ⟨a2⟩ over [0, t]); range over
    a2(0) = 0 and the rows).  Also requires Haff's −2 to be outside ci + allowance."""
    fit = late_slope(rows)
    a2 = [0.0] + [r["a2"] for r in rows]
    approach, sonine = abs(fit["theory"] + 5 / 3), 5 / 3 * KAPPA * (max(a2) - min(a2))
    band = fit["ci"] + approach + sonine
    agrees, haff = abs(fit["value"] + 5 / 3) <= band, abs(fit["value"] + 2) > band
    numbers = {**fit, "delta": rows[0]["delta"], "approach": approach, "sonine": sonine, "agrees": agrees,
               "haff_excluded": haff, "theory_agrees": abs(fit["value"] - fit["theory"]) <= fit["ci"] + sonine}
    word = "agrees with −5/3" if agrees else "differs from −5/3"
    text = (f"δ = {rows[0]['delta']:g}: late slope {fit['value']:.4f} ± {fit['ci']:.4f} (t ∈ [{fit['t_min']:g}, "
            f"{fit['t_max']:g}], {fit['times']} times) {word} within ci + allowance {approach + sonine:.4f} (approach "
            f"{approach:.4f}: the moment equation gives {fit['theory']:.4f}; first Sonine {sonine:.4f}); "
            + (f"Haff's −2 excluded ({abs(fit['value'] + 2):.2f} away)" if haff else "Haff's −2 NOT excluded"))
    return agrees and haff, numbers, text


def elastic_verdict(rows):
    """(ok, text) for the δ = 0 rows: T constant, |T/T(0) − 1| ≤ ELASTIC_TOL at every row."""
    worst = max(abs(r["rel_theory"]) for r in rows)
    ok = worst <= ELASTIC_TOL
    return ok, (f"δ = 0: T {'constant' if ok else 'NOT constant'} (max |T/T(0) − 1| = {worst:.1e} over "
                f"{len(rows)} times, t ≤ {rows[-1]['t']:g})")


def viscoelastic_verdict(rows):
    """(ok, per-δ numbers, text) over all rows: every δ > 0 by slope_verdict, δ = 0 by elastic_verdict."""
    ok, numbers, texts = True, [], []
    for delta in sorted({r["delta"] for r in rows}):
        mine = [r for r in rows if r["delta"] == delta]
        if delta == 0:
            good, text = elastic_verdict(mine)
        else:
            good, nums, text = slope_verdict(mine)
            numbers.append(nums)
        ok &= good
        texts.append(text)
    return ok, numbers, "; ".join(texts)


def short_verdict(ok, fits):
    """The report's one-line verdict: 'agrees: T ∝ t^(−5/3) (…)' or 'differs (…)', the late slope of each δ."""
    slopes = ", ".join(f"δ = {f['delta']:g}: {f['value']:.3f} ± {f['ci']:.3f}" for f in fits)
    haff = "Haff's −2 excluded" if all(f["haff_excluded"] for f in fits) else "Haff's −2 not excluded"
    return ("agrees: T ∝ t^(−5/3)" if ok else "differs") + f" (late slope {slopes}; {haff})"
