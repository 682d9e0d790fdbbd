"""Navier–Stokes transport coefficients of a dilute granular gas about its homogeneous cooling
state (HCS): shear viscosity eta, thermal conductivity kappa, the coefficient mu of the heat flux
along the density gradient (q = -kappa grad T - mu grad n) and self-diffusion D.

Two models, labelled as everywhere in the package:

- [exact] Maxwell molecules (lambda = 0) with the simulator's `geometry: uniform` collision map
  (GRW05 eq. 4: the outgoing relative velocity's direction e uniform on S^{d-1}), d = 2 and 3.
  Their collision moments of degree <= 4 are linear in moments of the same degree for any f, so
  the Chapman–Enskog coefficients are exact Boltzmann results. Per collision of particle 1 with
  an independent partner, v1' = s v1 + r v2 + b |u| e with s = (3 - alpha)/4, r = b = (1+alpha)/4,
  averaging over e (<e_i e_j> = delta_ij/d) gives, in units of the collision rate nu:
  cooling rate zeta = (1 - alpha^2)/4, anisotropy Pi = P - p I at nu_Pi = (1+alpha)(3-alpha)/8,
  heat-flux moment <v |v|^2> at nu_Q = 1 - s^3 - r^3 - (d+2) b^2/d ((1+alpha)(11-7alpha)/24 in
  d = 3), a tagged particle's mean velocity at nu_D = (1+alpha)/4.  The first-order
  Chapman–Enskog equations (the moment equations of degree 1-3 with the Euler time derivative
  acting on coefficients that scale as eta, D ~ T/nu, kappa ~ nT/(m nu), mu ~ T^2/(m nu), nu ~ n
  independent of T) give
      eta = p/(nu_Pi - zeta),       D = T/(m (nu_D - zeta)),
      kappa = (d+2) n T (1 + 2 a2)/(2 m (nu_Q - 2 zeta)),
      mu = [zeta T kappa/n + (d+2) a2 T^2/(2m)]/(nu_Q - 2 zeta),
  a2 the HCS Sonine coefficient (exact here: hcs_a2).  Elastic check: kappa = (15/4) eta/m in
  d = 3 (the Eucken value of Maxwell molecules).
- [approx] hard spheres (d = 3) and disks (d = 2, eta and D only): the standard first Sonine
  approximation (Brey, Dufty, Kim & Santos, PRE 58, 4638 (1998); Garzó & Dufty, PRE 59, 5895
  (1999)) and the modified one (Garzó, Santos & Montanero, Physica A 376, 94 (2007), the HCS as
  the weight), with the van Noije–Ernst a2 of the HCS.

Reduced units, as in the literature: each coefficient over its elastic value at the same n, T
(eta* = eta/eta0, kappa* = kappa/kappa0, D* = D/D0, mu* = n mu/(T kappa0)), so eta* = kappa* =
D* = 1 and mu* = 0 at alpha = 1.  For hard spheres these are the ratios of the formulas in
nu0 = p/eta0 units; D* here is D/D0 (the nu0-unit value times (d+2)/(2d)).
"""

import math

from .theory.dimension import check_dimension, check_geometry
from .theory.sonine import first_sonine_a2

COEFFICIENTS = ("eta", "kappa", "mu", "D")


# ----------------------------------------------------------------------------- Maxwell molecules
def _map_weights(alpha):
    a = float(alpha)
    return (3 - a) / 4, (1 + a) / 4, (1 + a) / 4  # s, r, b


def maxwell_rates(alpha, d=3, geometry="uniform"):
    """{zeta, Pi, Q, D}: the exact relaxation rates of lambda = 0 in units of the per-particle
    collision rate nu (module docstring) [exact]."""
    d = check_dimension(d, (2, 3), "transport.maxwell_rates")
    check_geometry(d, geometry, "transport.maxwell_rates", ("uniform",))
    a = float(alpha)
    s, r, b = _map_weights(a)
    return {"zeta": (1 - a * a) / 4, "Pi": (1 + a) * (3 - a) / 8,
            "Q": 1 - s**3 - r**3 - (d + 2) * b * b / d, "D": (1 + a) / 4}


def maxwell_fourth_moment_rates(alpha, d=3, geometry="uniform"):
    """(c4, c22) with d<|v|^4>/dt = nu (c4 <|v|^4> + c22 <|v|^2>^2) for an isotropic gas of zero
    mean velocity, lambda = 0, geometry uniform [exact]: E_e|v'|^4 = (|A|^2 + b^2 u^2)^2
    + 4 b^2 u^2 |A|^2/d with A = s v + r w, u = v - w, averaged over independent v, w
    (<(v.w)^2> = <|v|^2>^2/d).  In d = 3 these are maxwell_hierarchy.collision_coefficients(2)."""
    d = check_dimension(d, (2, 3), "transport.maxwell_fourth_moment_rates")
    check_geometry(d, geometry, "transport.maxwell_fourth_moment_rates", ("uniform",))
    s, r, b = _map_weights(alpha)
    k = 1 + 2 / d
    c4 = s**4 + r**4 + 2 * b * b * k * (s * s + r * r) + 2 * b**4 - 1
    c22 = 2 * s * s * r * r * k + 2 * b * b * k * (s * s + r * r - 4 * s * r / d) + 2 * b**4 * k
    return c4, c22


def maxwell_hcs_a2(alpha, d=3, geometry="uniform"):
    """a2 = <c^4>/(d(d+2)) - 1 of the lambda = 0 HCS (geometry uniform) [exact]: the scaled fourth
    moment's fixed point m4 = -c22 d^2/(c4 + 2 zeta); ValueError where it has none (the HCS
    fourth moment diverges)."""
    d = check_dimension(d, (2, 3), "transport.maxwell_hcs_a2")
    c4, c22 = maxwell_fourth_moment_rates(alpha, d, geometry)
    gap = c4 + 2 * maxwell_rates(alpha, d)["zeta"]
    if gap >= 0:
        raise ValueError(f"transport.maxwell_hcs_a2: the HCS fourth moment diverges at alpha = {alpha}")
    return -c22 * d * d / gap / (d * (d + 2)) - 1


def maxwell_coefficients(alpha, nu=1.0, n=1.0, T=1.0, m=1.0, d=3, geometry="uniform"):
    """{eta, kappa, mu, D} of lambda = 0 in the simulator's units [exact] (module docstring):
    nu the collision rate |S^{d-1}| gamma C at density n (any n: nu is taken as given).  kappa
    and mu are nan where nu_Q <= 2 zeta (alpha <= 1/5 in d = 3, 1/3 in d = 2): the heat
    flux then relaxes slower than the reference state cools, and has no Navier-Stokes form."""
    rates = maxwell_rates(alpha, d, geometry)
    a2 = maxwell_hcs_a2(alpha, d, geometry)
    zeta, p = rates["zeta"] * nu, n * T
    heat = rates["Q"] * nu - 2 * zeta
    if heat > 0:
        kappa = (d + 2) * n * T * (1 + 2 * a2) / (2 * m * heat)
        mu = (zeta * T * kappa / n + (d + 2) * a2 * T * T / (2 * m)) / heat
    else:  # the heat flux relaxes no faster than 2 zeta: no Navier-Stokes kappa, mu
        kappa = mu = math.nan
    return {"eta": p / (rates["Pi"] * nu - zeta), "kappa": kappa, "mu": mu,
            "D": T / (m * (rates["D"] * nu - zeta))}


def maxwell_reduced(alpha, d=3, geometry="uniform"):
    """{eta*, kappa*, mu*, D*} of lambda = 0 (each over its elastic value; mu* = n mu/(T kappa0))
    [exact]."""
    c = maxwell_coefficients(alpha, d=d, geometry=geometry)
    e = maxwell_coefficients(1.0, d=d, geometry=geometry)
    return {"eta": c["eta"] / e["eta"], "kappa": c["kappa"] / e["kappa"],
            "mu": c["mu"] / e["kappa"], "D": c["D"] / e["D"]}


# ----------------------------------------------------------------------------- hard spheres
def hard_sphere_zeta_star(alpha, a2, d=3):
    """zeta* = (d+2)(1 - alpha^2)(1 + 3 a2/16)/(4d): the HCS cooling rate in nu0 units
    (first Sonine)."""
    d = check_dimension(d, (2, 3), "transport.hard_sphere_zeta_star")
    return (d + 2) * (1 - alpha * alpha) * (1 + 3 * a2 / 16) / (4 * d)


def hard_sphere_reduced(alpha, version="standard", d=3, geometry=None):
    """{eta*, kappa*, mu*, D*} of hard spheres (d = 3) or {eta*, D*} of hard disks (d = 2, impact
    law) in the first Sonine approximation [approx], `version` "standard" (Brey–Dufty–Kim–Santos
    1998, Garzó–Dufty 1999) or "modified" (Garzó–Santos–Montanero 2007), each over its elastic
    value (module docstring), with the van Noije–Ernst HCS a2."""
    d = check_dimension(d, (2, 3), "transport.hard_sphere_reduced")
    if d == 2:
        check_geometry(d, geometry, "transport.hard_sphere_reduced")
    if version not in ("standard", "modified"):
        raise ValueError(f"transport.hard_sphere_reduced: version = {version!r}, not 'standard' or 'modified'")
    out = {}
    for key, a in (("value", float(alpha)), ("elastic", 1.0)):
        a2 = float(first_sonine_a2(a, "gaussian", 1, d, geometry))
        zeta = hard_sphere_zeta_star(a, a2, d)
        modified = version == "modified"
        nu_eta = 3 / (4 * d) * (1 - a + 2 * d / 3) * (1 + a) * ((1 + 7 * a2 / 16) if modified else (1 - a2 / 32))
        nu_D = (d + 2) * (1 + a) / (4 * d) * ((1 + 3 * a2 / 16) if modified else (1 - a2 / 32))
        c = {"eta": 1 / (nu_eta - zeta / 2), "D": 1 / (nu_D - zeta / 2)}
        if d == 3:
            nu_kappa = (1 + a) / 3 * (1 + 33 * (1 - a) / 16
                                      + ((947 - 579 * a) / 256 if modified else (19 - 3 * a) / 512) * a2)
            c["kappa"] = (d - 1) / d * (1 + 2 * a2) / (nu_kappa - 2 * zeta)
            c["mu"] = 2 * (zeta * c["kappa"] + (d - 1) * a2 / d) / (2 * nu_kappa - 3 * zeta)
        out[key] = c
    v, e = out["value"], out["elastic"]
    reduced = {"eta": v["eta"] / e["eta"], "D": v["D"] / e["D"]}
    if d == 3:
        reduced["kappa"] = v["kappa"] / e["kappa"]
        reduced["mu"] = v["mu"] / e["kappa"]
    return reduced


def hard_sphere_nu0_coefficients(alpha, version="standard", d=3, geometry=None):
    """The same coefficients in nu0 = p/eta0 units, as the literature tabulates them (eta*,
    kappa*, mu* are already so; D* = D m nu0/T, 2d/(d+2) at alpha = 1)."""
    r = hard_sphere_reduced(alpha, version, d, geometry)
    r["D"] = r["D"] * 2 * d / (d + 2)
    return r


# ----------------------------------------------------------------------------- measurements
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

    from .theory import LAMBDA_P

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

    from .theory import LAMBDA_P

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
