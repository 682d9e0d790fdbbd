"""TV06 (Talbot, Viot): the analytic formulas of Figs. 1-2, reading the simulator's intruder and
needle outputs, and the TV06 workflow scripts on synthetic HDF5 inputs with known answers."""

import csv
import json
import math

import h5py
import numpy as np
import pytest
import yaml
from scipy import integrate

from granboltz.report import COMPARE, render_md
from granboltz.theory import (colliding_density, colliding_mass, exact_temperature_ratio,
                              fluxes_by_quadrature, gaussian_fluxes, gaussian_temperature_ratio, powerlaw_pdf,
                              t_coverage)
from granboltz.reproduction.tv06_histograms import bin_average, folded_tail


LAMBDA_P = 3.2


# ----------------------------------------------------------------------------- synthetic outputs
def _stat(f, name, per):
    per = np.asarray(per, float)
    f[f"{name}/per_ensemble"] = per
    f[f"{name}/mean"] = per.mean()
    f[f"{name}/variance"] = per.var()  # the simulator's: over the ensembles, normalised by N
    f[f"{name}/ci"] = LAMBDA_P * math.sqrt(per.var() / per.size)


def _histogram(f, name, edges, density, ci, samples=10**13):
    width = edges[1] - edges[0]
    f[f"{name}/edges"] = edges
    f[f"{name}/density"] = density
    f[f"{name}/ci"] = ci
    f[f"{name}/counts"] = np.rint(density * width * samples).astype(np.uint64)
    f[f"{name}/overflow"] = np.zeros(2, dtype=np.uint64)


def _common(f, config, N, collisions, T_B, wall=1.0):
    f.attrs["config"] = yaml.safe_dump(config)
    f.attrs["ensembles"] = N
    f.attrs["version"], f.attrs["git_sha"] = "0.1.0", "abc123"
    prov = f.create_group("provenance")
    prov.attrs["wall_seconds"], prov.attrs["threads"] = wall, 2
    f["bath_temperature"] = T_B
    f["events/collisions"] = np.full(N, collisions, dtype=np.uint64)
    f["events/ensemble"] = np.arange(N, dtype=np.uint64)


def write_intruder(path, M, alpha, per, bath="gaussian", a=1.0, method="gillespie", collisions=1000, exact="auto",
                   histogram=None, fictitious=None):
    """An intruder output whose per-ensemble T/T_B are `per`; exact = the value of /exact (auto:
    the one the simulator writes), histogram = (edges, density, ci)."""
    config = {"model": "intruder", "seed": 1, "ensembles": len(per),
              "intruder": {"bath": {"kind": bath, "a": a}, "mass": M, "alpha": alpha, "density": 1,
                           "collisions": collisions, "warmup": collisions // 10, "method": method}}
    with h5py.File(path, "w") as f:
        _common(f, config, len(per), collisions, 1 / (2 * a) if bath == "gaussian" else 1 / a)
        _stat(f, "temperature_ratio", per)
        _stat(f, "mean_velocity", np.zeros(len(per)))
        if exact == "auto":
            exact = exact_temperature_ratio(bath, alpha, M)
        if exact is not None:
            f["exact/temperature_ratio"] = exact
        if histogram is not None:
            _histogram(f, "histogram", *histogram)
        if fictitious is not None:
            f["events/fictitious"] = np.full(len(per), fictitious, dtype=np.uint64)
            f["events/majorant_exceeded"] = np.full(len(per), 2, dtype=np.uint64)
    return str(path)


def write_needle(path, M, alpha, R, trans, rot, collisions=1000, omega=None):
    """A needle output with per-ensemble R, T_trans/T_B and T_rot/T_B; omega = (edges, density, ci)."""
    config = {"model": "needle", "seed": 1, "ensembles": len(R),
              "needle": {"mass": M, "length": 1, "alpha": alpha, "a": 1, "density": 1, "collisions": collisions,
                         "warmup": collisions // 10}}
    with h5py.File(path, "w") as f:
        _common(f, config, len(R), collisions, 0.5)
        _stat(f, "R", R)
        _stat(f, "translational_temperature_ratio", trans)
        _stat(f, "rotational_temperature_ratio", rot)
        if alpha == 1.0:
            for name in ("R", "translational_temperature_ratio", "rotational_temperature_ratio"):
                f[f"exact/{name}"] = 1.0
        if omega is not None:
            _histogram(f, "omega_histogram", *omega)
    return str(path)


def figure_outputs(tmp_path, name, csv=True):
    out = {"png": str(tmp_path / f"{name}.png"), "pdf": str(tmp_path / f"{name}.pdf"),
           "summary": str(tmp_path / f"{name}.json")}
    if csv:
        out["csv"] = str(tmp_path / f"{name}.csv")
    return out


def read_rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def assert_figure(out):
    png = open(out["png"], "rb").read()
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 10_000
    assert open(out["pdf"], "rb").read()[:5] == b"%PDF-"
    summary = json.load(open(out["summary"]))
    assert summary["ours"] and summary["short"]
    return summary


# ----------------------------------------------------------------------------- analytic (Figs. 1, 2)
@pytest.mark.parametrize("a,rho", [(0.5, 1.0), (1.0, 1.0), (2.0, 0.7), (4.0, 3.0)])
def test_gaussian_rates_at_rest_are_rho_over_sqrt_pi_a(a, rho):
    plus, minus, phi = gaussian_fluxes(0.0, a, rho)
    assert phi == pytest.approx(rho / math.sqrt(math.pi * a), rel=1e-15)
    assert plus == pytest.approx(minus, rel=1e-15)


def test_gaussian_rates_are_eqs_15_16_and_match_quadrature_of_eqs_5_6():
    v1 = np.linspace(-3, 3, 25)
    for a in (0.5, 1.0, 2.0, 4.0):
        plus, minus, phi = gaussian_fluxes(v1, a, 1.3)
        np.testing.assert_allclose(plus - minus, 1.3 * v1, atol=1e-14)  # phi_+ - phi_- = rho v1
        printed = 1.3 * (np.exp(-a * v1**2) / np.sqrt(np.pi * a) + v1 * np.vectorize(math.erf)(v1 * np.sqrt(a)))
        np.testing.assert_allclose(phi, printed, rtol=1e-13)  # eq. (16) as printed
        for x, p, m in zip(v1, plus, minus):
            qp, qm = fluxes_by_quadrature(x, a, 1.3)
            assert p == pytest.approx(qp, rel=1e-9, abs=1e-13) and m == pytest.approx(qm, rel=1e-9, abs=1e-13)
    assert gaussian_fluxes(3.0, 1.0)[0] == pytest.approx(3.0, rel=1e-4)  # phi ~ |v1| far out


@pytest.mark.parametrize("v1", [-2.0, -1.0, 0.0, 1.0, 2.0])
@pytest.mark.parametrize("side", [+1, -1])
def test_colliding_velocity_densities_integrate_to_one(v1, side):
    for a, rho in ((1.0, 1.0), (0.5, 2.0)):
        total = sum(integrate.quad(lambda v: float(colliding_density(v, v1, a, rho, side)), lo, hi)[0]
                    for lo, hi in ((-np.inf, v1), (v1, np.inf)))
        assert total == pytest.approx(1.0, abs=1e-10)
        assert colliding_mass(v1, a, -np.inf, np.inf, side) == pytest.approx(1.0, abs=1e-10)
    v = np.linspace(-6, 6, 121)
    g = colliding_density(v, v1, 1.0, side=side)
    assert np.all(g >= 0) and np.all(g[(v - v1) * side > 0] == 0)  # g_+ lives on v <= v1, g_- on v >= v1


def test_colliding_density_mean_is_the_ratio_of_moments():
    # for v1 = 0: <v> under g_+ = -<v^2 ; v<0> / <|v| ; v<0> = -sqrt(pi/(4a))
    mean = integrate.quad(lambda v: v * float(colliding_density(v, 0.0, 1.0)), -np.inf, 0)[0]
    assert mean == pytest.approx(-math.sqrt(math.pi) / 2, rel=1e-9)


def test_exact_temperature_ratios():
    assert gaussian_temperature_ratio(1.0, 0.3) == 1.0
    assert gaussian_temperature_ratio(0.0, 1.0) == pytest.approx(1 / 3)
    assert gaussian_temperature_ratio(0.5, 1.0) == pytest.approx(0.6)
    assert exact_temperature_ratio("powerlaw", 0.5, 0.5) == 0.5
    assert exact_temperature_ratio("powerlaw", 0.4, 0.5) is None
    assert exact_temperature_ratio("gaussian", 0.4, 0.5) == pytest.approx(1.4 / 3.2)
    assert integrate.quad(lambda v: powerlaw_pdf(v, 2.0), -np.inf, np.inf)[0] == pytest.approx(1.0)
    assert integrate.quad(lambda v: v * v * powerlaw_pdf(v, 2.0), -np.inf, np.inf)[0] == pytest.approx(0.5)
    assert t_coverage(10) == pytest.approx(0.9859, abs=1e-4) and t_coverage(10**6) == pytest.approx(0.9986, abs=1e-4)


def test_fig1_and_fig2_scripts_write_the_analytic_curves(run_script, tmp_path):
    out = figure_outputs(tmp_path, "tv06_fig1")
    run_script("tv06_collision_rates.py", output=out,
               params={"a": [0.5, 1.0, 2.0, 4.0], "rho": 1.0, "v1_range": [-3.0, 3.0], "table_step": 0.5})
    rows = read_rows(out["csv"])
    assert len(rows) == 4 * 13
    zero = {float(r["a"]): float(r["phi"]) for r in rows if float(r["v1"]) == 0.0}
    assert zero == pytest.approx({a: 1 / math.sqrt(math.pi * a) for a in (0.5, 1.0, 2.0, 4.0)}, rel=1e-10)
    numbers = assert_figure(out)["numbers"]
    assert numbers["quadrature_rel_error"] < 1e-8 and numbers["phi0_rel_error"] < 1e-14
    out = figure_outputs(tmp_path, "tv06_fig2")
    run_script("tv06_colliding_velocity.py", output=out,
               params={"a": 1.0, "rho": 1.0, "v1": [-2.0, 0.0, 2.0], "v_range": [-6.0, 3.0], "table_step": 0.01})
    rows = read_rows(out["csv"])
    for v1 in (-2.0, 0.0, 2.0):
        v = np.array([float(r["v"]) for r in rows if float(r["v1"]) == v1])
        g = np.array([float(r["g_plus"]) for r in rows if float(r["v1"]) == v1])
        assert np.trapz(g, v) == pytest.approx(1.0, abs=1e-3) and np.all(g[v > v1] == 0)
    summary = assert_figure(out)
    assert summary["numbers"]["normalisation_error"] < 1e-9
    assert 0 < summary["numbers"]["window_missing_mass"]["-2"] < 1e-4  # TV06's window [v1 - 2, v1]


# ----------------------------------------------------------------------------- Figs. 3, 4
def test_fig3_table_gives_the_exact_curve_and_the_simulators_ci(run_script, tmp_path):
    per_ok = [0.60, 0.61, 0.59, 0.60, 0.605, 0.595]
    runs = [write_intruder(tmp_path / "a.h5", 1.0, 0.5, per_ok),
            write_intruder(tmp_path / "b.h5", 1.0, 0.0, [0.40, 0.401, 0.399, 0.40, 0.4005, 0.3995]),
            write_intruder(tmp_path / "c.h5", 1.0, 1.0, [0.99, 1.01, 1.0, 1.0, 1.0, 1.0])]
    out = figure_outputs(tmp_path, "tv06_fig3")
    run_script("tv06_temperature_ratio.py", input={"runs": runs}, output=out)
    rows = read_rows(out["csv"])
    assert [float(r["alpha"]) for r in rows] == [0.0, 0.5, 1.0]
    assert [float(r["exact"]) for r in rows] == pytest.approx([1 / 3, 0.6, 1.0], rel=1e-6)
    ci = LAMBDA_P * np.std(per_ok) / math.sqrt(len(per_ok))
    assert float(rows[1]["ci"]) == pytest.approx(ci, rel=1e-5) and rows[1]["within_ci"] == "yes"
    assert float(rows[1]["z"]) == pytest.approx((np.mean(per_ok) - 0.6) / (ci / LAMBDA_P), abs=1e-4)
    assert rows[0]["within_ci"] == "no" and float(rows[0]["z"]) > 100  # 0.4 is far from 1/3
    summary = assert_figure(out)
    assert summary["numbers"]["inside"] == 2 and summary["short"].startswith("1 point(s) outside")


def test_fig3_refuses_an_exact_value_that_is_not_eq18(run_script, tmp_path):
    runs = [write_intruder(tmp_path / "a.h5", 1.0, 0.5, [0.6, 0.6, 0.61], exact=0.5)]
    with pytest.raises(ValueError, match="exact"):
        run_script("tv06_temperature_ratio.py", input={"runs": runs}, output=figure_outputs(tmp_path, "f"))


def test_fig4_marks_the_exact_points_and_compares_with_the_gaussian_curve(run_script, tmp_path):
    runs = []
    for M in (1.0, 0.5):
        for alpha in (0.0, 0.5, 1.0):
            T = float(gaussian_temperature_ratio(alpha, M)) * (1.2 if alpha < M else 1.0)
            runs.append(write_intruder(tmp_path / f"{M}_{alpha}.h5", M, alpha, [T - 0.01, T, T + 0.01],
                                       bath="powerlaw"))
    out = figure_outputs(tmp_path, "tv06_fig4")
    run_script("tv06_powerlaw_temperature.py", input={"runs": runs}, output=out)
    rows = read_rows(out["csv"])
    assert [(float(r["M"]), float(r["alpha"])) for r in rows if r["exact"]] == [(1.0, 1.0), (0.5, 0.5)]
    assert all(r["within_ci"] == "yes" for r in rows if r["exact"])
    summary = assert_figure(out)
    assert "M = 0.5: within 0.0 % of eq. (18) for α > M" in summary["short"] and "up to 20 % above" in summary["ours"]
    blocks, short = COMPARE["tv06_temperature"]("tv06_fig4", ours=rows)
    assert "indicative" in short and "infinite variance" in render_md(blocks)


# ----------------------------------------------------------------------------- Fig. 5
def _powerlaw_histogram(a=1.0, R=50.0, bins=10000):
    edges = np.linspace(-R, R, bins + 1)
    return edges, bin_average(lambda v: powerlaw_pdf(v, a), edges), np.full(bins, 1e-3)


def test_fig5_finds_the_v_minus_4_tail_and_the_exact_solution(run_script, tmp_path):
    hist = _powerlaw_histogram()
    runs = [write_intruder(tmp_path / f"{alpha}.h5", 0.5, alpha, [alpha, alpha, alpha], bath="powerlaw",
                           histogram=hist) for alpha in (0.0, 0.5)]
    out = figure_outputs(tmp_path, "tv06_fig5")
    run_script("tv06_powerlaw_distribution.py", input={"runs": runs}, output=out,
               params={"mass": 0.5, "v_max": 2.5, "bin_width": 0.05, "tail_from": 0.2, "tail_window": [5.0, 40.0],
                       "check_range": 5.0})
    summary = assert_figure(out)
    for fit in summary["numbers"]["exponents"].values():
        assert fit["exponent"] == pytest.approx(-4.0, abs=0.02)
    check = summary["numbers"]["check"]
    assert check["alpha"] == 0.5 and check["within"] == check["bins"] > 100
    rows = read_rows(out["csv"])
    assert {r["panel"] for r in rows} == {"linear", "tail"} and all(r["exact"] for r in rows if r["alpha"] == "0.5")


def test_folded_tail_rebins_exactly():
    edges = np.linspace(-10, 10, 2001)
    counts = np.arange(2000, dtype=np.uint64)
    hist = {"edges": edges, "counts": counts, "overflow": np.array([5, 7], dtype=np.uint64)}
    v, density, sums = folded_tail(hist, 0.5, bins_per_decade=5)
    centres = 0.5 * (edges[1:] + edges[:-1])
    assert sums.sum() == counts[np.abs(centres) >= 0.5].sum()
    assert np.all(np.diff(v) > 0) and np.all(density > 0)


# ----------------------------------------------------------------------------- Figs. 7, 8 (needle)
def test_fig7_table_gives_R_and_the_temperature_ordering(run_script, tmp_path):
    runs = [write_needle(tmp_path / "a.h5", 0.1, 0.1, [1.05, 1.06, 1.055], [0.066, 0.067, 0.0665],
                         [0.053, 0.054, 0.0535]),
            write_needle(tmp_path / "b.h5", 0.1, 0.5, [1.02, 1.03, 1.025], [0.30, 0.31, 0.30], [0.30, 0.31, 0.30]),
            write_needle(tmp_path / "c.h5", 0.1, 1.0, [0.99, 1.01, 1.0], [0.99, 1.01, 1.0], [1.0, 0.99, 1.01]),
            write_needle(tmp_path / "d.h5", 1.0, 0.1, [1.01, 1.0, 1.005], [0.3, 0.31, 0.305], [0.27, 0.28, 0.275])]
    out = figure_outputs(tmp_path, "tv06_fig7")
    run_script("tv06_needle_correlation.py", input={"runs": runs}, output=out)
    rows = read_rows(out["csv"])
    assert [(float(r["M"]), float(r["alpha"])) for r in rows] == [(0.1, 0.1), (0.1, 0.5), (0.1, 1.0), (1.0, 0.1)]
    assert float(rows[0]["R"]) == pytest.approx(1.055) and float(rows[0]["R_ci"]) == pytest.approx(
        LAMBDA_P * np.std([1.05, 1.06, 1.055]) / math.sqrt(3), rel=1e-5)
    assert [r["ordering"] for r in rows] == ["T_B > T_trans > T_rot", "not resolved", "equipartition",
                                             "T_B > T_trans > T_rot"]
    assert rows[2]["R_exact"] == "1" and float(rows[2]["R_z"]) == pytest.approx(0.0, abs=1e-9)
    assert float(rows[0]["trans_minus_rot"]) == pytest.approx(0.013)
    summary = assert_figure(out)
    assert summary["numbers"]["ordered"] == 2 and summary["numbers"]["inelastic"] == 3
    assert summary["numbers"]["R_low_alpha"] == pytest.approx({"0.1": 1.055, "1": 1.005})
    blocks, short = COMPARE["tv06_needle"]("tv06_fig7", ours=rows)
    assert short.startswith("check") and "2/3 points" in short


def test_fig8_fits_a_gaussian_to_a_gaussian(run_script, tmp_path):
    edges = np.linspace(-12, 12, 241)
    sigma = 1.8
    density = bin_average(lambda w: np.exp(-w**2 / (2 * sigma**2)) / math.sqrt(2 * math.pi * sigma**2), edges)
    runs = [write_needle(tmp_path / "n.h5", 0.1, 0.1, [1.05] * 4, [0.066] * 4, [0.053] * 4,
                         omega=(edges, density, np.full(240, 1e-4)))]
    out = figure_outputs(tmp_path, "tv06_fig8")
    run_script("tv06_needle_omega.py", input={"runs": runs}, output=out)
    numbers = assert_figure(out)["numbers"]
    assert numbers["s_fit"] == pytest.approx(sigma, rel=2e-3) and numbers["s_moments"] == pytest.approx(sigma, rel=2e-3)
    assert abs(numbers["excess_kurtosis"]) < 0.01
    rows = read_rows(out["csv"])
    assert len(rows) == 240 and {"omega", "density", "gaussian_fit", "gaussian_moments"} <= set(rows[0])


# ----------------------------------------------------------------------------- §4
def test_dsmc_table_compares_the_two_methods_with_the_joint_ci(run_script, tmp_path):
    g = [write_intruder(tmp_path / "g1.h5", 1.0, 0.5, [0.60, 0.601, 0.599]),
         write_intruder(tmp_path / "g2.h5", 2.0, 0.5, [0.667, 0.666, 0.667])]
    d = [write_intruder(tmp_path / "d1.h5", 1.0, 0.5, [0.600, 0.602, 0.598], method="dsmc", fictitious=12000),
         write_intruder(tmp_path / "d2.h5", 2.0, 0.5, [0.70, 0.701, 0.699], method="dsmc", fictitious=12000)]
    csv_path = tmp_path / "tv06_dsmc.csv"
    run_script("tv06_dsmc_table.py", input={"gillespie": g, "dsmc": d}, output={"csv": str(csv_path)})
    rows = read_rows(csv_path)
    assert [r["agree"] for r in rows] == ["yes", "no"]
    ci_g, ci_d = (LAMBDA_P * np.std(x) / math.sqrt(3) for x in ([0.60, 0.601, 0.599], [0.600, 0.602, 0.598]))
    assert float(rows[0]["joint_ci"]) == pytest.approx(math.hypot(ci_g, ci_d), rel=1e-5)
    assert float(rows[0]["exact"]) == pytest.approx(0.6) and float(rows[0]["candidates_per_collision"]) == 13.0
    assert float(rows[0]["ns_gillespie"]) == pytest.approx(1.0 * 2 / (3 * 1100) * 1e9, rel=1e-4)
    blocks, short = COMPARE["tv06_dsmc"]("tv06_dsmc", ours=rows)
    assert short.startswith("1 point(s) differ") and "1/2 points" in short


def test_dsmc_table_refuses_a_run_of_the_wrong_method(run_script, tmp_path):
    g = [write_intruder(tmp_path / "g.h5", 1.0, 0.5, [0.6, 0.6, 0.61])]
    with pytest.raises(ValueError, match="method dsmc"):
        run_script("tv06_dsmc_table.py", input={"gillespie": g, "dsmc": g}, output={"csv": str(tmp_path / "x.csv")})


# ----------------------------------------------------------------------------- workflow
def test_tv06_run_configs_carry_the_parameters(tmp_path):
    from test_workflow import snakemake
    from conftest import ROOT, load_config

    targets = {
        "fig4": "results/tv06/fig4/M=0.5/alpha=0.3/N=4/collisions=1000/run.yaml",
        "dsmc": "results/tv06/sec4_dsmc/M=2/alpha=0.8/N=4/collisions=1000/run.yaml",
        "fig8": "results/tv06/fig8/M=0.1/alpha=0.1/N=4/collisions=1000/run.yaml",
    }
    result = snakemake("--configfile", str(ROOT / "config" / "quick.yaml"), "--directory", str(tmp_path),
                       *targets.values())
    assert result.returncode == 0, result.stderr
    run = {k: yaml.safe_load((tmp_path / t).read_text()) for k, t in targets.items()}
    tv06 = load_config("quick")["tv06"]
    i = run["fig4"]["intruder"]
    assert run["fig4"]["model"] == "intruder" and run["fig4"]["ensembles"] == 4
    assert (i["bath"], i["mass"], i["alpha"], i["collisions"], i["method"]) == (
        {"kind": "powerlaw", "a": tv06["fig4"]["bath_a"]}, 0.5, 0.3, 1000, "gillespie")
    assert i["histogram"] == tv06["fig4"]["histogram"]
    i = run["dsmc"]["intruder"]
    assert (i["method"], i["bath"]["kind"], i["bath_particles"], i["bath_refresh"]) == (
        "dsmc", "gaussian", tv06["sec4"]["bath_particles"], "tested")
    n = run["fig8"]["needle"]
    assert run["fig8"]["model"] == "needle" and n["omega_histogram"] == tv06["fig8"]["omega_histogram"]
    assert (n["mass"], n["alpha"], n["length"], n["a"]) == (0.1, 0.1, tv06["needle"]["length"], tv06["needle"]["a"])
    assert len({r["seed"] for r in run.values()}) == 3


@pytest.mark.parametrize("spoil,message", [
    (lambda t: t["fig5"].update(mass=0.7), "tv06.fig5.mass"),
    (lambda t: t["fig5"].update(bin_width=0.013), "tv06.fig5.bin_width"),
    (lambda t: t["fig3"].update(alphas=[1.5]), "1.5"),
])
def test_workflow_checks_the_tv06_keys(tmp_path, spoil, message):
    from test_workflow import snakemake
    from conftest import load_config

    config = load_config("quick")
    spoil(config["tv06"])
    bad = tmp_path / "bad.yaml"
    bad.write_text(yaml.safe_dump(config))
    result = snakemake("--configfile", str(bad), "-n")
    assert result.returncode != 0 and message in result.stderr + result.stdout
