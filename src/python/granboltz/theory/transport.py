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

from .dimension import check_dimension, check_geometry
from .sonine import first_sonine_a2

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
