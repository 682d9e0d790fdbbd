"""Transport coefficients from the relaxation of a prepared state: a run started from an
anisotropic Maxwellian (`initial.temperature` a matrix: a shear stress P_xy) or with a heat
flux (`initial.heat_flux`) under the Gaussian thermostat, whose anisotropy or heat flux decays
while T is held. The decay rate r of the prepared quantity gives the coefficient through the
Chapman–Enskog relation about the homogeneous cooling state (granboltz.transport):

- shear stress: Pi_xy/p decays at r_Pi = nu_Pi - zeta under the thermostat, and
  eta = p/(nu_Pi - q zeta) with q the exponent of T in eta (eta ~ T^q: 1 for Maxwell molecules,
  1/2 for hard spheres), so eta = p/(r_Pi - (q - 1) zeta);
- heat flux: q/T^(3/2) decays at r_Q = nu_Q - 3 zeta/2, and kappa = (d+2) n T (1 + 2 a2)/(2 m
  (nu_Q - 2 zeta)) (the Maxwell form of transport.maxwell_coefficients; exact there, an
  approximation for hard spheres, whose nu_Q is not a single rate), so kappa uses
  r_Q - zeta/2 for every kernel: kappa ~ T^q and, since zeta ~ n T^(lambda/2), the Euler-order
  d(grad T)/dt = -(1 + lambda/2) zeta grad T, which add up to 2 zeta whatever lambda (the 2 zeta*
  of the Sonine kappa* of hard spheres).

For Maxwell molecules (lambda = 0) every step is exact: the decays are single exponentials at
the rates of transport.maxwell_rates. For hard spheres they are not (the relaxing state leaves
the first Sonine family), so the measured rate depends on the window, which the result records.

The interval of a rate: the least-squares slope of ln|x(t_m)| over the window's rows is a linear
combination sum_m w_m ln|x(t_m)| of rows whose correlation the output does not keep (they come
from the same ensembles), so its half-width is bounded by sum_m |w_m| ci_m (ci_m = ci(x_m)/|x_m|,
the rows' own half-widths at lambda_p): exact for perfectly correlated rows, conservative
otherwise, whatever the correlation. Measured over 30 replicas of the tests' Maxwell runs: the
replicas' spread is about half the sigma this bound claims. Replicas (a study's `replicas:`)
give the tight interval: the spread of the rates over independent runs.
"""

import math

import numpy as np


def decay_rate(t, x, ci, window=None):
    """The rate r of x(t) ~ A e^{-r t} over the rows with t in `window` = (t1, t2) (all rows by
    default): {"rate", "rate_ci", "amplitude", "rows", "window"}. ValueError where fewer than
    two rows are in the window or x changes sign there (no exponential decay to fit)."""
    t, x, ci = (np.asarray(v, dtype=float).ravel() for v in (t, x, ci))
    if not (t.shape == x.shape == ci.shape):
        raise ValueError(f"decay_rate: t, x and ci differ in length ({t.size}, {x.size}, {ci.size})")
    lo, hi = window if window is not None else (t.min(), t.max())
    keep = (t >= lo) & (t <= hi)
    if keep.sum() < 2:
        raise ValueError(f"decay_rate: {int(keep.sum())} rows in the window [{lo:g}, {hi:g}]; need 2")
    t, x, ci = t[keep], x[keep], ci[keep]
    if np.any(x == 0) or np.any(np.sign(x) != np.sign(x[0])):
        raise ValueError("decay_rate: the observable changes sign in the window; narrow it")
    y = np.log(np.abs(x))
    s = ci / np.abs(x)  # half-widths of ln|x|
    wts = 1.0 / s**2 if np.all(s > 0) else np.ones_like(s)  # exact rows: plain least squares
    tb = np.sum(wts * t) / np.sum(wts)
    # slope = sum_m w_m y_m with w_m = wts_m (t_m - tb)/sum wts (t - tb)^2
    w = wts * (t - tb) / np.sum(wts * (t - tb) ** 2)
    slope = float(np.sum(w * y))
    intercept = float(np.sum(wts * y) / np.sum(wts) - slope * tb)
    return {"rate": -slope, "rate_ci": float(np.sum(np.abs(w) * s)),
            "amplitude": math.copysign(math.exp(intercept), x[0]), "rows": int(keep.sum()),
            "window": (float(t[0]), float(t[-1]))}


def _thermostatted(run, what):
    section = run.config.get("dsmc", {})
    if section.get("thermostat") != "gaussian":
        raise ValueError(f"{what}: {getattr(run, 'path', 'run')} is not under the Gaussian "
                         "thermostat (the relaxation relations assume T held)")
    return section


def _exponent(section):
    """q of eta ~ T^q for the kernel C |u|^lambda: 1 - lambda/2."""
    return 1 - float((section.get("kernel") or {}).get("lambda", 1)) / 2


def viscosity_from_relaxation(run, window=None, zeta=0.0, zeta_ci=0.0, component=(0, 1)):
    """eta from the decay of a prepared shear stress P_ij (default xy) under the Gaussian
    thermostat: eta = p/(r_Pi - (q - 1) zeta), q = 1 - lambda/2; `zeta` the HCS cooling rate at
    the run's T (for Maxwell molecules q = 1 and it drops out). Returns decay_rate's dict with
    "eta", "eta_ci" and "p"."""
    section = _thermostatted(run, "viscosity_from_relaxation")
    P = run.observables["pressure_tensor"]
    i, j = component
    out = decay_rate(run.time, np.asarray(P.mean)[:, i, j], np.asarray(P.ci)[:, i, j], window)
    d = int(section.get("dimension", 3))
    p = float(np.trace(np.asarray(P.mean)[0, :d, :d]) / d)  # held by the thermostat
    shift = _exponent(section) - 1
    denom = out["rate"] - shift * zeta
    out.update(p=p, eta=p / denom,
               eta_ci=p * (out["rate_ci"] + abs(shift) * zeta_ci) / denom**2)
    return out


def conductivity_from_relaxation(run, a2, zeta, window=None, a2_ci=0.0, zeta_ci=0.0,
                                 component=0, m=1.0):
    """kappa from the decay of a prepared heat flux q_k (default x) under the Gaussian
    thermostat: kappa = (d+2) n T (1 + 2 a2)/(2 m (r_Q - zeta/2)) (any kernel), with the HCS a2 and
    cooling rate zeta at the run's T given (for Maxwell molecules exact from
    transport.maxwell_hcs_a2 and maxwell_rates, or measured). Returns decay_rate's dict with
    "kappa", "kappa_ci" (linear, each input's ci added) and "T"."""
    section = _thermostatted(run, "conductivity_from_relaxation")
    q = run.observables["heat_flux"]
    out = decay_rate(run.time, np.asarray(q.mean)[:, component], np.asarray(q.ci)[:, component],
                     window)
    d = int(section.get("dimension", 3))
    T = float(np.asarray(run.observables["temperature"].mean)[0])
    shift = 0.5  # T^q of kappa and the cooling of grad T add up to 2 zeta for every kernel
    denom = out["rate"] - shift * zeta
    kappa = (d + 2) * T * (1 + 2 * a2) / (2 * m * denom)
    kappa_ci = kappa * ((out["rate_ci"] + abs(shift) * zeta_ci) / abs(denom)
                        + 2 * a2_ci / (1 + 2 * a2))
    out.update(T=T, kappa=kappa, kappa_ci=kappa_ci)
    return out
