#!/usr/bin/python3
"""The Sonine constants of tests/engine/test_dimension.cpp, derived with exact symbolic Gaussian moments
(sympy; a few minutes). Run by hand: /usr/bin/python3 tests/sonine_moments.py

For f = M (1 + a2 S2 + a3 S3) (S_p the Laguerre polynomials L_p^(d/2-1) of c^2, M ~ exp(-c^2))
the collision moments J[psi] = E_{f x f}[|u|^lambda <psi(v') + psi(w') - psi(v) - psi(w)>_n] of
psi = c^2, c^4, c^6 are computed to first order in a2 and a3 (products dropped), with the impact
normal n of density ~ (u^.n)+ (hard spheres in d = 3, hard disks in d = 2) or, in d = 2, a
uniform impact angle (GRW05's e uniform on S^1). The steady moment equations then give a2 (first
Sonine: the c^4 equation with a3 = 0) and a2, a3 (second Sonine: the c^4 and c^6 equations):
  HCS (Gaussian thermostat): J4 / M4 = 2 J2 / M2, J6 / M6 = 3 J2 / M2,
  white noise:              J4 = 2 (d+2)/d J2 M2,  J6 = 3 (d+4)/d J2 M4.
For lambda = 0 these equations are exact (the hierarchy closes). The script checks itself against
every entry of reference/beyond.md §1 (d = 3 table, d = 2 first Sonine) and §2 (lambda = 0)."""

import sympy as sp
from sympy import Rational as R

AL = sp.symbols("alpha")


def solve(d, lam=1, geometry="impact"):
    r, c, S, a2, a3 = sp.symbols("r c S a2 a3")  # |u|, cos(theta), sin(theta)
    G = sp.symbols("G1:%d" % (d + 1))  # centre-of-mass velocity, components N(0, 1/4)
    g = [r] + [0] * (d - 1)
    n = [c, S] + [0] * (d - 2)
    gp = [g[i] - (1 + AL) * r * c * n[i] for i in range(d)]  # u' = u - (1 + alpha)(u.n) n
    sq = lambda v: sp.expand(sum(x * x for x in v))
    x1 = sq([G[i] + g[i] / 2 for i in range(d)])
    x2 = sq([G[i] - g[i] / 2 for i in range(d)])
    y1 = sq([G[i] + gp[i] / 2 for i in range(d)])
    y2 = sq([G[i] - gp[i] / 2 for i in range(d)])
    k = R(d, 2) - 1
    L = lambda p, x: sp.expand(sp.assoc_laguerre(p, k, x))
    weights = {0: sp.Integer(1), 2: L(2, x1) + L(2, x2), 3: L(3, x1) + L(3, x2)}
    th = sp.Symbol("th")

    def avg_G(e):
        out = 0
        for mon, co in sp.Poly(sp.expand(e), *G).terms():
            m = 1
            for p in mon:
                m = 0 if p % 2 else m * R(1, 4) ** (p // 2) * sp.factorial2(p - 1)
            out += co * m
        return sp.expand(out)

    def avg_angle(e):
        out = 0
        for (pc, ps), co in sp.Poly(sp.expand(e), c, S).terms():
            if ps % 2:
                continue
            f = sp.cos(th) ** pc * sp.sin(th) ** ps
            if d == 3:
                out += co * sp.integrate(f * 2 * sp.cos(th) * sp.sin(th), (th, 0, sp.pi / 2))
            else:
                dens = sp.cos(th) / 2 if geometry == "impact" else 1 / sp.pi
                out += co * sp.integrate(f * dens, (th, -sp.pi / 2, sp.pi / 2))
        return sp.expand(out)

    def avg_u(e):  # u ~ N(0, I_d), weight |u|^lambda
        out = 0
        for (p,), co in sp.Poly(sp.expand(e * r**lam), r).terms():
            out += co * 2 ** R(p, 2) * sp.gamma(R(d + p, 2)) / sp.gamma(R(d, 2))
        return sp.simplify(out)

    J = {}
    for p in (1, 2, 3):
        dpsi = sp.expand(y1**p + y2**p - x1**p - x2**p)
        J[p] = sum(w * avg_u(avg_angle(avg_G(dpsi * weights[key])))
                   for key, w in ((0, 1), (2, a2), (3, a3)))
    m2 = R(d, 2)
    m4 = R(d * (d + 2), 4) * (1 + a2)
    m6 = R(d * (d + 2) * (d + 4), 8) * (1 + 3 * a2 - a3)

    def linear(e):
        p = sp.Poly(sp.expand(e), a2, a3)
        return sum(co * a2**i * a3**j for (i, j), co in p.terms() if i + j <= 1)

    out = {}
    for name, (e4, e6) in {
        "hcs": (J[2] * m2 - 2 * J[1] * m4, J[3] * m2 - 3 * J[1] * m6),
        "wn": (J[2] - R(2 * (d + 2), d) * J[1] * m2, J[3] - R(3 * (d + 4), d) * J[1] * m4),
    }.items():
        first = sp.solve(linear(e4.subs(a3, 0)), a2)[0]
        sol = sp.solve([linear(e4), linear(e6)], [a2, a3])
        out[name] = (sp.factor(first), sp.factor(sol[a2]), sp.factor(sol[a3]))
    return out


def at(e, a):
    return float(e.subs(AL, a))


if __name__ == "__main__":
    alphas = [0.0, 0.2, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9]
    beyond = {  # reference/beyond.md §1
        (3, "hcs"): ([0.19753, 0.14990, 0.08469, 0.05246, 0.02386, 0.00131, -0.01258, -0.01456],
                     [0.12114, 0.10404, 0.06851, 0.04499, 0.02077, -0.00038, -0.01408, -0.01566],
                     [-0.12958, -0.08685, -0.03535, -0.01768, -0.00796, -0.00478, -0.00473,
                      -0.00387]),
        (3, "wn"): ([0.06639, 0.05701, 0.03772, 0.02560, 0.01288, 0.00079, -0.00868, -0.01179],
                    [0.06476, 0.05560, 0.03682, 0.02492, 0.01230, 0.00018, -0.00938, -0.01246],
                    [-0.00823, -0.00700, -0.00439, -0.00332, -0.00278, -0.00284, -0.00321,
                     -0.00291]),
        (2, "hcs"): ([0.28070, 0.22236, 0.13087, 0.08290, 0.03869, 0.00219, -0.02194, -0.02686],),
        (2, "wn"): ([0.08649, 0.07580, 0.05153, 0.03563, 0.01838, 0.00117, -0.01349, -0.01995],),
    }
    for d in (3, 2):
        res = solve(d)
        for name in ("hcs", "wn"):
            for column, expr in zip(beyond[(d, name)], res[name]):
                for a, v in zip(alphas, column):
                    assert abs(at(expr, a) - v) < 6e-6, (d, name, a, at(expr, a), v)
            first, s2, s3 = res[name]
            print(f"d = {d} hard, {name}: first Sonine a2 = {first}")
            for a in (0.5, 0.8, 0.9):
                print(f"  alpha {a}: vNE {at(first, a):.5f}, second Sonine a2 {at(s2, a):.5f}, "
                      f"a3 {at(s3, a):.5f}")
    # lambda = 0, d = 3: beyond.md §2 (exact)
    res = solve(3, lam=0)
    assert abs(at(res["hcs"][2], 0.5) + 0.72547) < 6e-6 and abs(at(res["wn"][2], 0.5) + 0.02718) < 6e-6
    for a in alphas:
        assert abs(at(res["hcs"][0], a) - 2 * (1 - a) ** 2 / (1 + 2 * a - a * a)) < 1e-12
        assert abs(at(res["wn"][0], a) - 2 * (1 - a) ** 2 * (1 + a) / (13 - 9 * a + a * a - a**3)) < 1e-12
    for geometry in ("impact", "uniform"):
        res = solve(2, lam=0, geometry=geometry)
        _, a2, a3 = res["wn"]
        print(f"d = 2 Maxwell, {geometry}, white noise (exact): a2 = {sp.factor(a2)}, a3 = {a3}")
        print(f"  alpha 0.5: a2 {at(a2, 0.5):.5f}, a3 {at(a3, 0.5):.5f}")
    print("all checks against beyond.md passed")
