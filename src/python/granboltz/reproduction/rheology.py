"""The rheology of uniform shear flow as a table (`shear_rheology`): for each steady sheared run
the reduced shear rate, the temperature and the pressure tensor over the pressure, P_ij/p, each
with its interval, beside the exact values of Maxwell molecules (lambda = 0) or the nonlinear
Grad closure of hard spheres (d = 3).

Intervals (at the simulator's lambda_p, as every ci of an output):
- P_ij/p under the Gaussian thermostat: p is held exactly (T is the thermostat's), so the ci of
  P_ij over p.
- P_ij/p without a thermostat: p fluctuates with P_ij, and the output keeps no covariance of the
  two, so the ci is the linear bound |r| (ci_ij/|P_ij| + ci_p/p), which holds whatever their
  correlation (conservative: it assumes the worst one).
- the reduced shear rate of hard spheres, a/nu0(T) ~ T^(-1/2): half the relative ci of T.
Theory: Maxwell molecules exact with `geometry: uniform` (d = 2 disks with the default impact
law have none here); hard spheres the Grad closure in d = 3 only (none for disks).
Units as granboltz.shear's: density 1, nu = |S^{d-1}| gamma C for Maxwell molecules, nu0 =
p/eta0 of elastic hard spheres at the run's T (shear.hard_sphere_nu0).
"""

import math

import numpy as np

from ..theory import LAMBDA_P, shear

COMPONENTS = (("xx", 0, 0), ("yy", 1, 1), ("zz", 2, 2), ("xy", 0, 1))
COLUMNS = (["model", "d", "thermostat", "alpha", "shear_rate", "shear_rate_ci", "temperature",
            "temperature_ci"]
           + [c for name, _, _ in COMPONENTS for c in (f"P{name}_p", f"P{name}_p_ci")]
           + ["theory", "shear_rate_theory", "temperature_theory"]
           + [f"P{name}_p_theory" for name, _, _ in COMPONENTS] + ["path"])


def _model(section, path):
    lam = float((section.get("kernel") or {}).get("lambda", 1))
    if lam == 0:
        return "maxwell"
    if lam == 1:
        return "hard_spheres"
    raise ValueError(f"shear_rheology: {path}: dsmc.kernel.lambda = {lam:g}; the table has "
                     "Maxwell molecules (0) and hard spheres (1)")


def shear_rheology_row(run):
    """One row of the table from a steady sheared run (dsmc.shear.rate and dsmc.steady_from)."""
    section = run.config.get("dsmc", {})
    path = getattr(run, "path", "run")
    a = float((section.get("shear") or {}).get("rate", 0.0))
    if a == 0.0:
        raise ValueError(f"shear_rheology: {path} has no dsmc.shear.rate")
    if "pressure_tensor" not in run.steady:
        raise ValueError(f"shear_rheology: {path} has no steady average (dsmc.steady_from)")
    alpha = section.get("alpha")
    if not isinstance(alpha, (int, float)):
        raise ValueError(f"shear_rheology: {path}: dsmc.alpha = {alpha!r}; the table needs a "
                         "constant restitution coefficient")
    alpha = float(alpha)
    d = int(section.get("dimension", 3))
    thermostat = section.get("thermostat", "none") or "none"
    gamma = float(section.get("gamma", 1.0))
    C = float((section.get("kernel") or {}).get("C", 1.0))
    model = _model(section, path)

    P, Tst = run.steady["pressure_tensor"], run.steady["temperature"]
    Pm, Pci = np.asarray(P.mean, dtype=float), np.asarray(P.ci, dtype=float)
    T, T_ci = float(np.asarray(Tst.mean)), float(np.asarray(Tst.ci))
    p = float(np.trace(Pm[:d, :d])) / d
    held = thermostat == "gaussian"
    row = {"model": model, "d": d, "thermostat": thermostat, "alpha": alpha,
           "temperature": T, "temperature_ci": T_ci, "path": str(path)}
    for name, i, j in COMPONENTS:
        if i >= d or j >= d:
            row[f"P{name}_p"] = row[f"P{name}_p_ci"] = math.nan
            continue
        r = Pm[i, j] / p
        if held:
            ci = Pci[i, j] / p
        else:
            ci = abs(r) * (Pci[i, j] / abs(Pm[i, j]) + T_ci / p) if Pm[i, j] != 0 else Pci[i, j] / p
        row[f"P{name}_p"], row[f"P{name}_p_ci"] = r, ci

    theory = {}
    geometry = section.get("geometry") or ("impact" if d == 2 else "uniform")
    if model == "maxwell":
        nu = (4 * math.pi if d == 3 else 2 * math.pi) * gamma * C
        row["shear_rate"], row["shear_rate_ci"] = a / nu, 0.0
        row["theory"], row["shear_rate_theory"], row["temperature_theory"] = "", a / nu, math.nan
        if geometry == "uniform":  # the exact second moments are those of e uniform on S^{d-1}
            # The ratios settle on the dominant eigenvector with or without the thermostat.
            G = shear.maxwell_gaussian_usf_ratios(alpha, a, gamma, C, d=d)
            theory = {name: G[i, j] for name, i, j in COMPONENTS if i < d and j < d}
            row["theory"] = "exact"
    else:
        nu0 = shear.hard_sphere_nu0(T, gamma, C, d=d)
        row["shear_rate"] = a / nu0
        row["shear_rate_ci"] = 0.5 * row["shear_rate"] * T_ci / T
        row["theory"], row["shear_rate_theory"], row["temperature_theory"] = "", math.nan, math.nan
        if d == 3 and held:
            theory = shear.hard_sphere_usf_grad_gaussian(alpha, row["shear_rate"])
            row["theory"], row["shear_rate_theory"] = "grad", row["shear_rate"]
        elif d == 3:
            grad = shear.hard_sphere_usf_grad(alpha, a, gamma, C)
            theory = grad
            row["theory"] = "grad"
            row["shear_rate_theory"], row["temperature_theory"] = grad["reduced_shear_rate"], grad["T"]
    for name, _, _ in COMPONENTS:
        row[f"P{name}_p_theory"] = theory.get(name, math.nan)
    return row


def shear_rheology(runs):
    """The `shear_rheology` table of these runs (a pandas DataFrame, columns COLUMNS), sorted by
    model, d, thermostat, alpha and shear rate."""
    import pandas as pd

    rows = [shear_rheology_row(run) for run in runs]
    frame = pd.DataFrame(rows, columns=COLUMNS)
    return frame.sort_values(["model", "d", "thermostat", "alpha", "shear_rate"],
                             ignore_index=True)


RHEOLOGY_COMPONENTS = ("xx", "yy", "zz", "xy")


def rheology_verdict(rows):
    """(ours, short, kind) over shear_rheology rows (granboltz.rheology, as floats): each
    component of a row with theory "exact" against it within the row's interval (✗ where one is
    outside), the Grad rows (hard spheres, an approximation) by their largest sigma-distance."""
    exact, far, grad = 0, [], []
    for r in rows:
        for name in RHEOLOGY_COMPONENTS:
            value, ci, ref = r.get(f"P{name}_p"), r.get(f"P{name}_p_ci"), r.get(f"P{name}_p_theory")
            if any(v is None or math.isnan(v) for v in (value, ci, ref)):
                continue
            z = (value - ref) / (ci / LAMBDA_P) if ci > 0 else (0.0 if value == ref else math.inf)
            if r["theory"] == "exact":
                exact += 1
                if abs(value - ref) > ci:
                    far.append(f"**P{name}/p of λ = 0 at α = {r['alpha']:g}, a* = {r['shear_rate']:.3g}: "
                               f"{value:.4f} ± {ci:.4f} vs exact {ref:.4f}**")
            elif r["theory"] == "grad":
                grad.append((abs(z), z, name, r))
    parts, short = [], []
    if exact:
        parts.append(f"λ = 0 exact: {exact - len(far)} of {exact} components within their interval")
        short.append(f"λ = 0 exact {exact - len(far)}/{exact}")
    parts += far
    if grad:
        _, z, name, r = max(grad, key=lambda g: g[0])
        parts.append(f"hard spheres vs the nonlinear Grad closure: largest distance {z:+.1f}σ (P{name}/p, "
                     f"{r['thermostat']}, α = {r['alpha']:g}, a* = {r['shear_rate']:.3g})")
        short.append(f"Grad closure (approximation) within {abs(z):.1f}σ")
    kind = "differs" if far else ("agrees" if exact else "approximation")
    return "; ".join(parts) or "no rows", "; ".join(short) or "no rows", kind
