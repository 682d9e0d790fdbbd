"""The `transport_coefficients` table and its verdict: measured Navier–Stokes coefficients (eta*,
kappa*, mu*, D*, reduced as in granboltz.theory.transport) beside the exact lambda = 0 values and
both first Sonine approximations of hard spheres.

Each *method* is one function `rows(runs, **params) -> [row]` registered in METHODS; a row
carries model, d, alpha, coefficient, method, value, ci (at lambda_p); `complete_rows` fills the
theory columns and `transport_verdict` judges them: a lambda = 0 row further than its interval
from the exact value is a failure (✗), the only one this table can show; a hard-sphere row
favours the closer Sonine version by so many sigma (sigma = ci/lambda_p), is "not resolved"
where the versions part by less than its interval, and "neither within" outside both.

Methods (analysis.relaxation, analysis.transport), all Gaussian-thermostatted; hard spheres use
the first Sonine HCS a2 and zeta (common to both versions, so they favour neither):
- "relaxation": eta from a prepared shear stress; kappa and mu from the decay rate r_Q of a
  prepared heat flux (mu from the same decay through Chapman–Enskog, not from a density
  gradient). Exact for lambda = 0, the moment closure of the Sonine theories for hard spheres.
- "usf": eta from steady shear flow extrapolated to a -> 0; the thermostat's p/(nu_Pi - zeta)
  turned into the Navier–Stokes p/(nu_Pi - q zeta).
- "green_kubo": eta, D (and kappa, mu in d = 3) from the time correlations of the HCS
  (green_kubo_coefficient). Exact for lambda = 0; for hard spheres the autocorrelation stands in
  for the correlation with the HCS's conjugate function.
"""

import math

from ..analysis import transport as measured
from ..theory import LAMBDA_P
from ..theory import transport
from ..theory.shear import hard_sphere_nu0
from ..theory.sonine import first_sonine_a2

COLUMNS = ["model", "d", "alpha", "coefficient", "method", "value", "ci", "exact", "sonine_standard",
           "sonine_modified"]
MODELS = {0.0: "maxwell", 1.0: "hard_spheres"}


def run_physics(run):
    """(model, d, alpha, T, gamma, C, geometry) of a run's config; ValueError for another
    kernel or a restitution law other than a constant alpha."""
    section = run.config.get("dsmc", {})
    path = getattr(run, "path", "run")
    lam = float((section.get("kernel") or {}).get("lambda", 1))
    if lam not in MODELS:
        raise ValueError(f"transport table: {path}: dsmc.kernel.lambda = {lam:g}; the table has 0 and 1")
    alpha = section.get("alpha")
    if not isinstance(alpha, (int, float)):
        raise ValueError(f"transport table: {path}: dsmc.alpha = {alpha!r}; a constant alpha is needed")
    d = int(section.get("dimension", 3))
    geometry = section.get("geometry") or ("impact" if d == 2 else "uniform")
    T0 = (section.get("initial") or {}).get("temperature", 1.0)
    T = T0 if isinstance(T0, (int, float)) else sum(T0[k][k] for k in range(d)) / d
    return (MODELS[lam], d, float(alpha), float(T), float(section.get("gamma", 1.0)),
            float((section.get("kernel") or {}).get("C", 1.0)), geometry)


def scales(model, d, alpha, T, gamma, C, geometry):
    """The reference scales at density 1 and m = 1: {"zeta", "a2", "q", "eta0", "kappa0"} with
    eta0, kappa0, D0 the elastic values the reduced coefficients divide by (transport's reduction):
    lambda = 0 the exact ones at nu = |S^{d-1}| gamma C; hard spheres the first Sonine ones
    (eta0 = p/nu0, kappa0 = d(d+2) eta0/(2(d-1)), D0 = 2d eta0/((d+2) n m)) and the first Sonine
    HCS zeta and a2."""
    if model == "maxwell":
        nu = (4 * math.pi if d == 3 else 2 * math.pi) * gamma * C
        elastic = transport.maxwell_coefficients(1.0, nu=nu, T=T, d=d, geometry=geometry)
        return {"zeta": transport.maxwell_rates(alpha, d, geometry)["zeta"] * nu,
                "a2": transport.maxwell_hcs_a2(alpha, d, geometry), "q": 1.0,
                "eta0": elastic["eta"], "kappa0": elastic["kappa"], "D0": elastic["D"]}
    nu0 = hard_sphere_nu0(T, gamma, C, d=d)
    a2 = float(first_sonine_a2(alpha, "gaussian", 1, d, geometry if d == 2 else None))
    eta0 = T / nu0
    return {"zeta": transport.hard_sphere_zeta_star(alpha, a2, d) * nu0, "a2": a2, "q": 0.5,
            "eta0": eta0, "kappa0": d * (d + 2) * eta0 / (2 * (d - 1)), "D0": 2 * d * eta0 / (d + 2)}


def row(model, d, alpha, coefficient, method, value, ci):
    """One measured row (theory columns empty until complete_rows)."""
    return {"model": model, "d": int(d), "alpha": float(alpha), "coefficient": coefficient, "method": method,
            "value": float(value), "ci": float(ci)}


# ----------------------------------------------------------------------------- methods
def relaxation_rows(runs, window=None):
    """Rows of the method "relaxation" from runs under the Gaussian thermostat with a prepared
    shear stress (initial.temperature a matrix: eta*) or heat flux (initial.heat_flux: kappa*
    and, in d = 3, mu*)."""
    from ..analysis.relaxation import conductivity_from_relaxation, viscosity_from_relaxation

    out = []
    for run in runs:
        model, d, alpha, T, gamma, C, geometry = run_physics(run)
        s = scales(model, d, alpha, T, gamma, C, geometry)
        initial = run.config["dsmc"].get("initial") or {}
        if "heat_flux" in initial:
            fit = conductivity_from_relaxation(run, s["a2"], s["zeta"], window=window)
            T = fit["T"]
            out.append(row(model, d, alpha, "kappa", "relaxation", fit["kappa"] / s["kappa0"],
                           fit["kappa_ci"] / s["kappa0"]))
            if d == 3 and (s["zeta"] > 0 or s["a2"] != 0):  # elastic: mu = 0 identically, nothing measured
                denom = fit["rate"] + (0.5 - s["q"]) * s["zeta"]
                source = s["zeta"] * T * fit["kappa"] + (d + 2) * s["a2"] * T * T / 2
                mu = source / denom
                # linear in kappa and 1/denom: the two cis added (both from the one rate)
                mu_ci = (s["zeta"] * T * fit["kappa_ci"] + abs(mu) * fit["rate_ci"]) / abs(denom)
                out.append(row(model, d, alpha, "mu", "relaxation", mu / (T * s["kappa0"]),
                               mu_ci / (T * s["kappa0"])))
        elif not isinstance(initial.get("temperature", 1.0), (int, float)):
            fit = viscosity_from_relaxation(run, window=window, zeta=s["zeta"])
            out.append(row(model, d, alpha, "eta", "relaxation", fit["eta"] / s["eta0"], fit["eta_ci"] / s["eta0"]))
        else:
            raise ValueError(f"relaxation_rows: {getattr(run, 'path', 'run')} has no prepared shear stress or heat flux")
    return out


def usf_rows(runs, order=3):
    """Rows of the method "usf": eta* of each (model, d, alpha) group of sheared runs at a -> 0
    (transport.usf_viscosity) through a^4: a^2 alone takes the exact lambda = 0 rheology 0.4 % low."""
    groups = {}
    for run in runs:
        groups.setdefault(run_physics(run)[:3], []).append(run)
    out = []
    for (model, d, alpha), group in sorted(groups.items()):
        _, _, _, T, gamma, C, geometry = run_physics(group[0])
        s = scales(model, d, alpha, T, gamma, C, geometry)
        fit = measured.usf_viscosity(group, order=order)
        p = T
        # thermostat's eta = p/(nu_Pi - zeta) -> Navier-Stokes p/(nu_Pi - q zeta)
        shift = (1 - s["q"]) * s["zeta"]
        eta = p / (p / fit["eta"] + shift)
        eta_ci = fit["eta_ci"] * (eta / fit["eta"]) ** 2
        out.append(row(model, d, alpha, "eta", "usf", eta / s["eta0"], eta_ci / s["eta0"]))
    return out


def green_kubo_rows(runs):
    """Rows of the method "green_kubo": eta* from the shear-stress, D* from the tagged-velocity and
    (d = 3) kappa*, mu* from the heat-flux time correlation of runs in the thermostatted HCS
    (dsmc.correlations), each integrated with its granular weight
    (transport.green_kubo_coefficient; kappa and mu with the a2 and zeta of `scales`)."""
    out = []
    for run in runs:
        model, d, alpha, T, gamma, C, geometry = run_physics(run)
        s = scales(model, d, alpha, T, gamma, C, geometry)
        path = getattr(run, "path", run)
        wanted = [("eta", s["eta0"]), ("D", s["D0"])]
        if d == 3:
            wanted += [("kappa", s["kappa0"])] + ([("mu", T * s["kappa0"])] if s["zeta"] > 0 or s["a2"] != 0 else [])
        for coefficient, reference in wanted:
            value, ci = measured.green_kubo_coefficient(path, coefficient, T=T, zeta=s["zeta"], q=s["q"], d=d,
                                                         a2=s["a2"])
            out.append(row(model, d, alpha, coefficient, "green_kubo", value / reference, ci / reference))
    return out


METHODS = {"relaxation": relaxation_rows, "usf": usf_rows, "green_kubo": green_kubo_rows}


# ----------------------------------------------------------------------------- theory and table
def theory(model, d, alpha, coefficient):
    """(exact, sonine_standard, sonine_modified) for one row, nan where a column does not apply
    (no exact value for hard spheres, no Sonine values for lambda = 0, none for kappa and mu of
    hard disks)."""
    nan = math.nan
    if model == "maxwell":
        value = transport.maxwell_reduced(alpha, d=d).get(coefficient, nan)
        return value, nan, nan
    geometry = "impact" if d == 2 else None
    std = transport.hard_sphere_reduced(alpha, "standard", d, geometry).get(coefficient, nan)
    mod = transport.hard_sphere_reduced(alpha, "modified", d, geometry).get(coefficient, nan)
    return nan, std, mod


def complete_rows(rows):
    """The table: every row with its theory columns, sorted by model, d, coefficient, alpha and
    method (COLUMNS)."""
    order = {c: k for k, c in enumerate(transport.COEFFICIENTS)}
    out = []
    for r in rows:
        exact, std, mod = theory(r["model"], r["d"], r["alpha"], r["coefficient"])
        out.append({**r, "exact": exact, "sonine_standard": std, "sonine_modified": mod})
    return sorted(out, key=lambda r: (r["model"], r["d"], order[r["coefficient"]], r["alpha"], r["method"]))


def build_table(inputs):
    """The table from {method: (runs, params)}: each method's rows, completed."""
    rows = []
    for method, (runs, params) in inputs.items():
        if method not in METHODS:
            raise ValueError(f"build_table: method {method!r}; known: {', '.join(METHODS)}")
        rows += METHODS[method](runs, **params)
    return complete_rows(rows)


def _z(value, ref, ci):
    return (value - ref) / (ci / LAMBDA_P) if ci > 0 else (0.0 if value == ref else math.inf)


def sonine_preference(r):
    """For a hard-sphere row: (favoured version or None when unresolved, z_standard,
    z_modified), the z signed sigma-distances of the value from each version. The favoured
    version is the closer one, named "<version>, neither within" when the value lies outside its
    interval around both ("neither within" alone where the versions are not resolved)."""
    zs, zm = _z(r["value"], r["sonine_standard"], r["ci"]), _z(r["value"], r["sonine_modified"], r["ci"])
    if math.isnan(zs) or math.isnan(zm):
        return None, zs, zm
    if abs(r["sonine_standard"] - r["sonine_modified"]) < r["ci"]:
        # the versions part by less than the interval: not resolved (and said so if outside both)
        return (None if min(abs(zs), abs(zm)) <= LAMBDA_P else "neither within"), zs, zm
    closer = "standard" if abs(zs) < abs(zm) else "modified"
    return (closer if min(abs(zs), abs(zm)) <= LAMBDA_P else f"{closer}, neither within"), zs, zm


def preference_text(favoured):
    """sonine_preference's first value in words: the favoured version, or why there is none."""
    return {None: "not resolved", "neither within": "not resolved, neither within"}.get(favoured, favoured)


# The elastic limit: the Chapman–Enskog eta, kappa and D of elastic hard spheres (d = 3) exceed
# their first Sonine values by these factors, the converged Sonine series of rigid spheres (eta,
# kappa: Chapman & Cowling, The Mathematical Theory of Non-Uniform Gases, 3rd ed. 1970; D: the
# dilute-limit value the hard-sphere molecular-dynamics literature quotes, e.g. Erpenbeck & Wood,
# Phys. Rev. A 43, 4254 (1991)).
ELASTIC_HARD_SPHERES = {"eta": 1.016034, "kappa": 1.025218, "D": 1.01896}


def elastic_limit(rows):
    """The alpha = 1 hard-sphere rows (d = 3) with a converged elastic value: [(row, factor, z,
    z_sonine)], z the sigma-distance from the Chapman–Cowling factor and z_sonine from the first
    Sonine value 1: the elastic difference is resolved where |z| <= lambda_p < |z_sonine|."""
    out = []
    for r in rows:
        factor = ELASTIC_HARD_SPHERES.get(r["coefficient"])
        if r["model"] == "hard_spheres" and r["d"] == 3 and r["alpha"] == 1.0 and factor:
            out.append((r, factor, _z(r["value"], factor, r["ci"]), _z(r["value"], 1.0, r["ci"])))
    return out


def sonine_tally_text(tally, rows):
    """The hard-sphere rows counted once each, by sonine_preference's first value: favouring a
    version within its interval, closer to one but outside both, or with versions that part by
    less than the interval (of which so many lie outside both)."""
    t = lambda key: tally.get(key, 0)  # noqa: E731
    unresolved = t(None) + t("neither within")
    return (f"hard spheres, {rows} rows: {t('modified')} favour modified Sonine, {t('standard')} standard; "
            f"{t('modified, neither within')} closer to modified but outside both, "
            f"{t('standard, neither within')} closer to standard; {unresolved} not resolved "
            f"({t('neither within')} of them outside both)")


def transport_verdict(rows):
    """(ours, short, kind) over complete rows: kind "differs" if a lambda = 0 row lies outside
    its interval around the exact value, else "agrees" when there are exact rows, else
    "approximation"; the texts give the worst exact distance and, for hard spheres, which
    Sonine version each resolved row favours and by how many sigma."""
    exact = [r for r in rows if r["model"] == "maxwell" and not math.isnan(r["exact"])]
    far = [r for r in exact if abs(r["value"] - r["exact"]) > r["ci"]]
    parts, short = [], []
    if exact:
        worst = max(abs(_z(r["value"], r["exact"], r["ci"])) for r in exact)
        parts.append(f"λ = 0 exact: {len(exact) - len(far)} of {len(exact)} rows within their interval "
                     f"(max {worst:.1f}σ)")
        short.append(f"λ = 0 exact {len(exact) - len(far)}/{len(exact)} (max {worst:.1f}σ)")
    for r in far:
        parts.append(f"**{r['coefficient']} ({r['method']}, d = {r['d']}, α = {r['alpha']:g}) differs from "
                     f"the exact {r['exact']:.4f}: {r['value']:.4f} ± {r['ci']:.4f}**")
    hs = [r for r in rows if r["model"] == "hard_spheres"]
    tally = {"standard": 0, "modified": 0, None: 0}
    for r in hs:
        favoured, zs, zm = sonine_preference(r)
        tally[favoured] = tally.get(favoured, 0) + 1
        which = f"favours {favoured}" if favoured and favoured != "neither within" else preference_text(favoured)
        parts.append(f"{r['coefficient']}* {r['method']} d = {r['d']} α = {r['alpha']:g}: {r['value']:.4f} ± "
                     f"{r['ci']:.4f} vs standard {r['sonine_standard']:.4f} ({zs:+.1f}σ), modified "
                     f"{r['sonine_modified']:.4f} ({zm:+.1f}σ): {which}")
    if hs:
        short.append(sonine_tally_text(tally, len(hs)))
    for r, factor, z, z1 in elastic_limit(rows):
        resolved = abs(z) <= LAMBDA_P < abs(z1)
        parts.append(f"elastic limit: {r['coefficient']}* {r['method']} {r['value']:.4f} ± {r['ci']:.4f} vs the "
                     f"converged Chapman–Enskog {factor:.4f} ({z:+.1f}σ) and the first Sonine 1 ({z1:+.1f}σ): "
                     + ("resolved" if resolved else "not resolved" if abs(z) <= LAMBDA_P else "differs"))
    kind = "differs" if far else ("agrees" if exact else "approximation")
    return "; ".join(parts) if parts else "no rows", "; ".join(short) if short else "no rows", kind


def csv_rows(rows):
    """Complete rows for the CSV: nan theory columns as None (written empty: does not apply)."""
    return [{k: (None if isinstance(v, float) and math.isnan(v) and k in COLUMNS[7:] else v) for k, v in r.items()}
            for r in rows]


def read_rows(rows):
    """CSV rows (strings) back as complete rows: numbers as floats, empty cells as nan."""
    out = []
    for r in rows:
        x = dict(r)
        x["d"], x["alpha"] = int(float(r["d"])), float(r["alpha"])
        for k in ("value", "ci") + tuple(COLUMNS[7:]):
            x[k] = math.nan if r.get(k) in (None, "", "nan") else float(r[k])
        out.append(x)
    return out
