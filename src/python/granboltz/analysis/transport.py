"""Transport coefficients measured on runs (the theory is granboltz.theory.transport): the
Green–Kubo integrals of the simulator's time correlations (dsmc.correlations) with their
intervals, and the shear viscosity of thermostatted uniform shear flow extrapolated to a -> 0.
Units and models as granboltz.theory.transport's."""

import math

def usf_viscosity(runs, order=2):
    """The shear viscosity from steady uniform shear flow under the Gaussian thermostat,
    extrapolated to zero shear rate: eta(a) = -P_xy/a of each run (its steady average; T, hence
    p, is held exactly by the thermostat), fitted by eta0 + c1 a^2 + ... (even in a, `order` terms
    in all) with weights from each run's own interval, which is honest for a steady average
    (blocking or batch). Returns {"eta": eta0, "eta_ci": its half-width at lambda_p, "points":
    [(a, eta, eta_ci)], "chi2": the fit's chi-square, "dof"}.

    What it measures: under the Gaussian thermostat the small-a response is the integral of the
    thermostatted stress autocorrelation without the Chapman-Enskog weight, p/(nu_Pi - zeta) for
    a single exponential. For Maxwell molecules (q = 1) that is the Navier-Stokes eta exactly
    (maxwell_coefficients); for hard spheres (q = 1/2) the Navier-Stokes value is p/(nu_Pi -
    zeta/2), which a thermostatted shear flow does not give: there it measures the thermostat's
    own viscosity, larger by about zeta/(2 (nu_Pi - zeta)) relatively."""
    import numpy as np

    from ..theory import LAMBDA_P

    points = []
    for run in runs:
        section = run.config.get("dsmc", {})
        a = float((section.get("shear") or {}).get("rate", 0.0))
        if a == 0.0:
            raise ValueError(f"usf_viscosity: {run.path} has no dsmc.shear.rate")
        if section.get("thermostat") != "gaussian":
            raise ValueError(f"usf_viscosity: {run.path} is not under the Gaussian thermostat (p must be held)")
        if "pressure_tensor" not in run.steady:
            raise ValueError(f"usf_viscosity: {run.path} has no steady average (dsmc.steady_from)")
        P = run.steady["pressure_tensor"]
        points.append((a, -float(np.asarray(P.mean)[0, 1]) / a, float(np.asarray(P.ci)[0, 1]) / abs(a)))
    if len(points) < order:
        raise ValueError(f"usf_viscosity: {len(points)} runs for a fit of {order} terms")
    a = np.array([p[0] for p in points])
    y = np.array([p[1] for p in points])
    sigma = np.array([p[2] for p in points]) / LAMBDA_P
    X = np.stack([a ** (2 * k) for k in range(order)], axis=1)
    W = 1.0 / sigma**2
    cov = np.linalg.inv(X.T @ (W[:, None] * X))
    beta = cov @ (X.T @ (W * y))
    chi2 = float(np.sum(W * (y - X @ beta) ** 2))
    return {"eta": float(beta[0]), "eta_ci": float(LAMBDA_P * math.sqrt(cov[0, 0])), "points": points,
            "chi2": chi2, "dof": len(points) - order}


def correlation_integral(lags, mean, covariance, ensembles, weight_rate=0.0, prefactor=1.0, t_max=None):
    """A Green-Kubo integral and its interval: prefactor * int_0^tmax rho(t) e^{-w t} dt of a
    normalised time correlation rho given at `lags` (increasing times from 0) as its mean over
    `ensembles` independent ensembles and their covariance across lags (the ensembles' spread,
    not the error of the mean). The integral is the trapezoid rule on the lags, a linear
    functional c . rho, so its variance is c^T covariance c / ensembles: the correlation between
    lags that a sum of per-lag intervals would miss is in it. w = weight_rate: (1 - q) zeta for
    the stress of a coefficient scaling as T^q (0 for Maxwell molecules), (1/2 - q) zeta for the
    velocity (negative for Maxwell molecules: the weight grows). Returns (value, ci) with ci at
    the level of lambda_p (Student-t with N - 1 degrees of freedom below 30 ensembles, as the
    simulator's steady intervals). The tail beyond the last lag (or beyond t_max, when given) is
    left out: choose lags that reach where rho is 0."""
    import numpy as np
    from scipy import stats

    from ..theory import LAMBDA_P

    t = np.asarray(lags, dtype=float)
    rho = np.asarray(mean, dtype=float)
    cov = np.asarray(covariance, dtype=float)
    if t.ndim != 1 or len(t) < 2 or t[0] != 0 or np.any(np.diff(t) <= 0):
        raise ValueError("correlation_integral: lags must be increasing times starting at 0")
    if rho.shape != t.shape or cov.shape != (len(t), len(t)):
        raise ValueError(f"correlation_integral: {len(t)} lags, mean of shape {rho.shape}, covariance of shape {cov.shape}")
    if ensembles < 2:
        raise ValueError("correlation_integral: an interval needs at least 2 ensembles")
    if t_max is not None:
        keep = t <= t_max
        if keep.sum() < 2:
            raise ValueError(f"correlation_integral: t_max = {t_max!r} keeps fewer than 2 lags")
        t, rho, cov = t[keep], rho[keep], cov[np.ix_(keep, keep)]
    h = np.diff(t)
    c = np.zeros_like(t)
    c[:-1] += h / 2
    c[1:] += h / 2
    c *= np.exp(-weight_rate * t) * prefactor
    z = LAMBDA_P if ensembles >= 30 else float(stats.t.ppf(0.5 + math.erf(LAMBDA_P / math.sqrt(2)) / 2, ensembles - 1))
    return float(c @ rho), float(z * math.sqrt(max(c @ cov @ c, 0.0) / ensembles))


def read_correlation(path, name):
    """One time correlation of an output with dsmc.correlations: /correlations/<name> (name
    `velocity`, `velocity/<species>`, `stress`, `normal_stress` or `heat_flux`) as a dict of numpy
    arrays lag, mean, ci, covariance and the floats lag0, lag0_ci, ensembles, with the group's
    attributes (every, from, points, averaging, levels, channels, samples). mean is normalised by
    each ensemble's own lag-0 value; lag0 is that value's mean (docs/output.md)."""
    import h5py
    import numpy as np

    with h5py.File(path, "r") as f:
        key = f"correlations/{name}"
        if key not in f:
            have = sorted(f["correlations"]) if "correlations" in f else []
            raise KeyError(f"{path}: no /{key} (it has {', '.join(have) or 'no dsmc.correlations'})")
        g = f[key]
        out = {k: np.asarray(g[k][()], dtype=float) for k in ("lag", "mean", "ci", "covariance")}
        out.update(lag0=float(g["lag0"][()]), lag0_ci=float(g["lag0_ci"][()]),
                   ensembles=int(f.attrs["ensembles"]) if "ensembles" in f.attrs else len(f["events/ensemble"]))
        out.update({k: v.item() if hasattr(v, "item") else v for k, v in g.attrs.items() if k != "description"})
    return out


def green_kubo(path, name, weight_rate=0.0, prefactor=1.0):
    """A Green-Kubo integral of a stored correlation: prefactor * lag0 * int rho(t) e^{-w t} dt
    with its interval (correlation_integral's, with lag0's relative interval added linearly: a
    bound whatever their correlation). Under the Gaussian thermostat at temperature T and unit
    density the self-diffusion is D = green_kubo(path, "velocity", (1/2 - q) zeta), q = 1 - lambda/2
    (the velocity's lag0 is T). The stress's lag0 is <c_x^2 c_y^2> = T^2 (1 + a2), not n T^2:
    green_kubo(path, "stress", (1 - q) zeta, 1/T) is eta (1 + a2) for Maxwell molecules, and
    green_kubo_coefficient, which scales by the exact n T, is the viscosity. Returns (value, ci)."""
    c = read_correlation(path, name)
    value, ci = correlation_integral(c["lag"], c["mean"], c["covariance"], c["ensembles"], weight_rate, prefactor)
    total = value * c["lag0"]
    return total, abs(total) * (ci / abs(value) + c["lag0_ci"] / c["lag0"]) if value else c["lag0"] * ci


def integration_cutoff(lags, mean, weight_rate=0.0, decay_times=6.0):
    """Where to stop a Green–Kubo integral: the first lag t with t >= decay_times * I(t), I(t) the
    running trapezoid integral of rho(t) e^{-w t}. For an integrand that decays as one exponential
    I tends to its decay time, so the cut leaves out e^{-decay_times} of the integral (0.25 % at 6)
    while the noise of the longer lags, which a growing weight (w < 0) amplifies, stays out.
    None when no lag qualifies (the correlator's lags end first: integrate them all)."""
    import numpy as np

    t = np.asarray(lags, dtype=float)
    f = np.asarray(mean, dtype=float) * np.exp(-weight_rate * t)
    running = np.concatenate([[0.0], np.cumsum(np.diff(t) * (f[1:] + f[:-1]) / 2)])
    hit = np.nonzero((t > 0) & (t >= decay_times * running))[0]
    return float(t[hit[0]]) if len(hit) else None


def green_kubo_coefficient(path, coefficient, T, zeta, q, d=3, a2=0.0, n=1.0, m=1.0, decay_times=6.0):
    """A Navier–Stokes coefficient of the thermostatted HCS from its Green–Kubo form (Dufty, Brey
    and co-workers: Brey, Ruiz-Montero, Maynar, García de Soria, J. Phys.: Condens. Matter 17
    (2005) S2489): the normalised time correlation rho(t) of the flux (read_correlation), integrated
    with the weight of a coefficient scaling as T^q, times the equal-time value of the flux's
    response to its gradient in the local HCS (the Chapman–Enskog source term):
        eta   = n T                       int rho_stress(t)    e^{-(1 - q) zeta t} dt
        D     = (T/m)                     int rho_velocity(t)  e^{-(1/2 - q) zeta t} dt
        kappa = (d+2) n T (1 + 2 a2)/(2m) int rho_heat_flux(t) e^{+zeta t/2} dt
        mu    = (zeta T kappa/n + (d+2) a2 T^2/(2m)) int rho_heat_flux(t) e^{-(1/2 - q) zeta t} dt
    with zeta, a2 of the HCS and the gas under the Gaussian thermostat at temperature T.
    [exact] for Maxwell molecules (lambda = 0, q = 1): the normalised correlations are single
    exponentials at the rates of the moment equations (nu_Pi - zeta, nu_D - zeta/2,
    nu_Q - 3 zeta/2), so these give maxwell_coefficients. [approx] otherwise: the Green–Kubo
    correlation is with the HCS's conjugate function, which differs from the flux itself at O(a2);
    the normalised autocorrelation stands in for it (the lag-0 amplitude, which differs at O(a2)
    too, e.g. <c_x^2 c_y^2> = T^2 (1 + a2), is replaced by the exact source term). Each integral
    stops after `decay_times` of its own decay time (integration_cutoff). Returns
    (value, ci) with ci at lambda_p (correlation_integral; for mu the two integrals' intervals
    added: a bound whatever their correlation)."""
    names = {"eta": "stress", "D": "velocity", "kappa": "heat_flux", "mu": "heat_flux"}
    if coefficient not in names:
        raise ValueError(f"green_kubo_coefficient: coefficient = {coefficient!r}; known: {', '.join(names)}")
    c = read_correlation(path, names[coefficient])

    def integral(weight_rate, prefactor):
        t_max = integration_cutoff(c["lag"], c["mean"], weight_rate, decay_times)
        return correlation_integral(c["lag"], c["mean"], c["covariance"], c["ensembles"], weight_rate, prefactor, t_max)

    if coefficient == "eta":
        return integral((1 - q) * zeta, n * T)
    if coefficient == "D":
        return integral((0.5 - q) * zeta, T / m)
    kappa, kappa_ci = integral(-zeta / 2, (d + 2) * n * T * (1 + 2 * a2) / (2 * m))
    if coefficient == "kappa":
        return kappa, kappa_ci
    source = zeta * T * kappa / n + (d + 2) * a2 * T * T / (2 * m)
    tau, tau_ci = integral((0.5 - q) * zeta, 1.0)
    return source * tau, abs(source) * tau_ci + zeta * T * kappa_ci / n * abs(tau)
