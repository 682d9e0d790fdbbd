"""The report section "Transport and rheology": the comparisons of the tables
`transport_coefficients` (granboltz.reproduction.transport_table) and `shear_rheology`
(granboltz.reproduction.rheology), whose verdicts those modules compute."""

import math

from ..reproduction.rheology import RHEOLOGY_COMPONENTS, rheology_verdict
from ..reproduction.transport_table import preference_text, read_rows, sonine_preference, transport_verdict
from .numbers import DASH, Verdict, num, pm

TRANSPORT = "Transport and rheology"
INTRO = ("Navier–Stokes transport coefficients of the homogeneous cooling state and the rheology of uniform shear "
         "flow (`dsmc.shear`), measured with the Gaussian thermostat: η* from the relaxation of a prepared shear "
         "stress and from steady shear flow extrapolated to a → 0, κ* and μ* from the relaxation of a prepared heat "
         "flux, and η*, D*, κ*, μ* from Green–Kubo integrals of the time correlations of the thermostatted HCS "
         "(`dsmc.correlations`; docs/physics.md; `granboltz.relaxation`, `granboltz.transport`). Maxwell molecules (λ = 0, "
         "`geometry: uniform`) are exact Boltzmann results and the ✓/✗ check; hard spheres are compared with the "
         "standard (Brey–Dufty–Kim–Santos 1998, Garzó–Dufty 1999) and the modified (Garzó–Santos–Montanero 2007) "
         "first Sonine approximations. Reduced as in the literature: each coefficient over its elastic value "
         "(μ* = nμ/(Tκ0)). Rule file `workflow/rules/transport.smk`; table and verdict in "
         "`granboltz.transport_table`.")


def _f(x):
    return None if x is None or (isinstance(x, float) and math.isnan(x)) else x


def compare_transport_coefficients(name, ours, published=None, **_):
    """transport_coefficients: every row with its exact or Sonine values and sigma-distances."""
    rows = read_rows(ours)
    header = ["model", "d", "α", "coefficient", "method", "ours ± CI", "exact", "standard Sonine", "modified Sonine",
              "favoured"]
    body = []
    for r in rows:
        favoured = DASH
        if r["model"] == "hard_spheres":
            which, zs, zm = sonine_preference(r)
            favoured = f"{preference_text(which)} ({zs:+.1f}σ / {zm:+.1f}σ)"
        elif not math.isnan(r["exact"]):
            z = (r["value"] - r["exact"]) / (r["ci"] / 3.2) if r["ci"] > 0 else 0.0
            favoured = f"exact {z:+.1f}σ"
        body.append([r["model"].replace("_", " "), r["d"], num(r["alpha"]), r["coefficient"], r["method"],
                     pm(r["value"], r["ci"], 4), num(_f(r["exact"]), 4), num(_f(r["sonine_standard"]), 4),
                     num(_f(r["sonine_modified"]), 4), favoured])
    text, short, kind = transport_verdict(rows)
    note = ("σ-distances are (ours − theory)/(CI/λ_p), signed: standard / modified. A hard-sphere row is 'not "
            "resolved' where the two Sonine values part by less than its interval. For hard spheres the HCS a2 and ζ "
            "entering the conversions are first-Sonine values (common to both versions); the relaxation of a "
            "hard-sphere state is not a single exponential, so the fitted window is part of the result. μ* comes "
            "from the same heat-flux decay as κ* (Chapman–Enskog), not from a density gradient. The prepared heat "
            "flux (`initial.heat_flux`) is carried by slow particles (its perturbation is damped by e^{−c²/2}), not "
            "by the Chapman–Enskog form c(c² − 5/2) f_M; for λ = 0 that does not matter (the degree-3 moments "
            "close), for hard spheres slow particles collide less and the decay is slower, so κ* and μ* of hard "
            "spheres by relaxation lean high: the elastic row (α = 1, Chapman–Enskog κ* = 1.025 in these units) "
            "shows by how much. η* relaxes from an anisotropic Maxwellian, which is the Chapman–Enskog form. "
            "Green–Kubo rows integrate the normalised autocorrelation of the flux (stress, tagged velocity, heat "
            "flux) with its Chapman–Enskog weight, to six of its own decay times, times the exact source term "
            "(nT, T/m, (d+2)nT(1+2a2)/2m): exact for λ = 0; for hard spheres the autocorrelation stands in for "
            "the correlation with the HCS's conjugate function. κ*'s weight e^{ζt/2} grows, so its interval is the "
            "widest.")
    return [("table", header, body), ("ul", [text + ".", note])], Verdict(kind, short)


def compare_shear_rheology(name, ours, published=None, **_):
    """shear_rheology: P_ij/p per run beside the exact lambda = 0 or the Grad values."""
    keys = ["alpha", "shear_rate", "shear_rate_ci", "temperature", "temperature_ci"] + [
        f"P{c}_p{s}" for c in RHEOLOGY_COMPONENTS for s in ("", "_ci", "_theory")]
    rows = []
    for r in ours:
        x = dict(r)
        for k in keys:
            x[k] = math.nan if r.get(k) in (None, "", "nan") else float(r[k])
        rows.append(x)
    header = ["model", "d", "thermostat", "α", "a*", "theory"] + [f"P{c}/p (theory)" for c in RHEOLOGY_COMPONENTS]
    body = [[r["model"].replace("_", " "), r["d"], r["thermostat"], num(r["alpha"]), num(r["shear_rate"], 4),
             r["theory"] or DASH]
            + [DASH if math.isnan(r[f"P{c}_p"]) else
               f"{pm(r[f'P{c}_p'], r[f'P{c}_p_ci'], 4)} ({num(_f(r[f'P{c}_p_theory']), 4)})"
               for c in RHEOLOGY_COMPONENTS] for r in rows]
    text, short, kind = rheology_verdict(rows)
    note = ("λ = 0 rows: the exact second-moment solution of the σ-uniform map (granboltz.shear); hard spheres: the "
            "nonlinear Grad closure (transport.md §2), an approximation. a* = a/ν (λ = 0) or a/ν0(T) (hard spheres).")
    return [("table", header, body), ("ul", [text + ".", note])], Verdict(kind, short)


def transport_section(items, data, item_blocks):
    """The section "Transport and rheology": intro and its registered items; (blocks, summary rows)."""
    from .summary import summary_rows

    blocks, parts = [("h", 2, TRANSPORT), ("p", INTRO)], []
    for it in (it for it in items if it["paper"] == TRANSPORT):
        item, short = item_blocks(it, data)
        blocks += item
        parts.append((it, short))
    return blocks, summary_rows(TRANSPORT, parts)
