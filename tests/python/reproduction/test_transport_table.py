"""The transport_coefficients table (granboltz.transport_table) from synthetic runs whose observables
decay exactly at a known rate: the lambda = 0 rows meet the exact Chapman–Enskog values
(transport.maxwell_reduced, derived separately), hard-sphere rows made at the first Sonine rates
give back the Sonine kappa* and mu* (the 2 zeta of kappa for every kernel), and the verdict's
exact check, Sonine preference and refusals."""

import math
import types

import numpy as np
import pytest

from granboltz.reproduction import transport_table
from granboltz.theory import transport
from granboltz.theory.shear import hard_sphere_nu0
from granboltz.theory.sonine import first_sonine_a2

T_GRID = np.linspace(0, 3, 13)


def _observable(mean, ci):
    return types.SimpleNamespace(mean=np.asarray(mean), ci=np.asarray(ci))


def _run(lam, alpha, initial, rate, d=3, C=1 / (4 * math.pi), rel_ci=1e-4):
    section = {"alpha": alpha, "gamma": 1.0, "kernel": {"lambda": lam, "C": C}, "thermostat": "gaussian",
               "dimension": d, "initial": initial}
    if d == 2:
        section["geometry"] = "impact"
    decay = np.exp(-rate * T_GRID)
    P = np.tile(np.eye(d), (len(T_GRID), 1, 1)).astype(float)
    P[:, 0, 1] = P[:, 1, 0] = 0.4 * decay
    q = np.zeros((len(T_GRID), d))
    q[:, 0] = 0.19 * decay
    obs = {"pressure_tensor": _observable(P, np.abs(P) * rel_ci),
           "heat_flux": _observable(q, np.abs(q) * rel_ci),
           "temperature": _observable(np.ones(len(T_GRID)), np.zeros(len(T_GRID)))}
    return types.SimpleNamespace(config={"dsmc": section}, time=T_GRID, observables=obs, steady={}, path="synthetic")


SHEAR = {"temperature": [[1, 0.4, 0], [0.4, 1, 0], [0, 0, 1]]}
HEAT = {"heat_flux": [0.19, 0, 0]}


@pytest.mark.parametrize("alpha", [0.5, 0.8])
def test_maxwell_rows_meet_the_exact_reduced_coefficients(alpha):
    r = transport.maxwell_rates(alpha)  # nu = 1 with C = 1/(4 pi)
    runs = [_run(0, alpha, SHEAR, r["Pi"] - r["zeta"]), _run(0, alpha, HEAT, r["Q"] - 1.5 * r["zeta"])]
    rows = transport_table.build_table({"relaxation": (runs, {})})
    exact = transport.maxwell_reduced(alpha)
    assert [x["coefficient"] for x in rows] == ["eta", "kappa", "mu"]
    for x in rows:
        assert list(x) == transport_table.COLUMNS
        assert x["value"] == pytest.approx(exact[x["coefficient"]], rel=1e-9, abs=1e-12)
        assert math.isnan(x["sonine_standard"]) and x["exact"] == pytest.approx(exact[x["coefficient"]])
    ours, short, kind = transport_table.transport_verdict(rows)
    assert kind == "agrees" and "3 of 3" in ours


def _sonine_nu_kappa(alpha, a2):
    return (1 + alpha) / 3 * (1 + 33 * (1 - alpha) / 16 + (19 - 3 * alpha) * a2 / 512)


@pytest.mark.parametrize("alpha", [0.3, 0.5, 0.9])
def test_hard_sphere_heat_flux_at_the_standard_sonine_rate_gives_its_kappa_and_mu(alpha):
    # The standard first Sonine nu_kappa* in nu0 units decays q/T^(3/2) at nu_kappa - 3 zeta/2
    # under the thermostat; kappa* then needs r_Q - zeta/2 (2 zeta in all), not r_Q.
    C = 1 / (4 * math.pi)
    nu0 = hard_sphere_nu0(1.0, 1.0, C)
    a2 = float(first_sonine_a2(alpha, "gaussian", 1, 3, None))
    zeta = transport.hard_sphere_zeta_star(alpha, a2)
    rate = (_sonine_nu_kappa(alpha, a2) - 1.5 * zeta) * nu0
    rows = transport_table.build_table({"relaxation": ([_run(1, alpha, HEAT, rate, C=C)], {})})
    std = transport.hard_sphere_reduced(alpha, "standard")
    by = {x["coefficient"]: x for x in rows}
    assert by["kappa"]["value"] == pytest.approx(std["kappa"], rel=1e-9)
    assert by["mu"]["value"] == pytest.approx(std["mu"], rel=1e-9, abs=1e-12)
    assert by["kappa"]["sonine_standard"] == pytest.approx(std["kappa"]) and math.isnan(by["kappa"]["exact"])


def test_hard_disk_viscosity_at_the_modified_rate_is_favoured_as_modified():
    alpha, C = 0.3, 1 / (2 * math.pi)
    nu0 = hard_sphere_nu0(1.0, 1.0, C, d=2)
    a2 = float(first_sonine_a2(alpha, "gaussian", 1, 2, "impact"))
    zeta = transport.hard_sphere_zeta_star(alpha, a2, d=2)
    nu_eta = 3 / 8 * (1 - alpha + 4 / 3) * (1 + alpha) * (1 + 7 * a2 / 16)
    rows = transport_table.build_table({"relaxation": ([_run(1, alpha, {"temperature": [[1, 0.4], [0.4, 1]]},
                                                            (nu_eta - zeta) * nu0, d=2, C=C)], {})})
    (x,) = rows
    assert x["d"] == 2 and x["value"] == pytest.approx(x["sonine_modified"], rel=1e-9)
    favoured, zs, zm = transport_table.sonine_preference(x)
    assert favoured == "modified" and abs(zm) < 1e-3 < abs(zs)
    ours, short, kind = transport_table.transport_verdict(rows)
    assert kind == "approximation" and "1 favour modified" in short and "favours modified" in ours


def test_the_verdict_fails_only_on_an_exact_row_outside_its_interval():
    rows = transport_table.complete_rows([transport_table.row("maxwell", 3, 0.5, "eta", "usf", 1.2, 0.01),
                                          transport_table.row("hard_spheres", 3, 0.9, "eta", "usf", 1.0, 0.5)])
    ours, short, kind = transport_table.transport_verdict(rows)
    assert kind == "differs" and "differs from the exact" in ours
    assert "not resolved" in ours  # the versions part by far less than 0.5 at alpha = 0.9
    exact = transport.maxwell_reduced(0.5)["eta"]
    next(r for r in rows if r["model"] == "maxwell")["value"] = exact + 0.009
    assert transport_table.transport_verdict(rows)[2] == "agrees"


def test_a_method_is_one_function_and_unknown_ones_are_refused(monkeypatch):
    monkeypatch.setitem(transport_table.METHODS, "green_kubo",
                        lambda runs, **_: [transport_table.row("maxwell", 3, 0.5, "D", "green_kubo", 1.0, 0.1)])
    rows = transport_table.build_table({"green_kubo": ([], {})})
    assert rows[0]["exact"] == pytest.approx(transport.maxwell_reduced(0.5)["D"])
    with pytest.raises(ValueError, match="method 'nope'"):
        transport_table.build_table({"nope": ([], {})})
    run = _run(0.5, 0.5, SHEAR, 1.0)
    with pytest.raises(ValueError, match="lambda = 0.5"):
        transport_table.relaxation_rows([run])


def test_the_report_reads_the_csv_rows_back_and_marks_them():
    """The section's comparisons take the CSV cells (strings, empty where a column does not apply)."""
    from granboltz.report.document import COMPARE

    rows = transport_table.csv_rows(transport_table.complete_rows([
        transport_table.row("maxwell", 3, 0.5, "eta", "relaxation", transport.maxwell_reduced(0.5)["eta"], 0.02),
        transport_table.row("hard_spheres", 3, 0.3, "kappa", "relaxation", 1.9, 0.1)]))
    cells = [{k: "" if v is None else (f"{v:.6g}" if isinstance(v, float) else str(v)) for k, v in r.items()}
             for r in rows]
    assert cells[0]["exact"] == "" and cells[1]["sonine_standard"] == ""  # hard spheres first, maxwell second
    blocks, verdict = COMPARE["transport_coefficients"](name="transport_coefficients", ours=cells)
    assert verdict.kind == "agrees" and "favours modified" in blocks[1][1][0]
    rheology = [{"model": "maxwell", "d": "3", "thermostat": "gaussian", "alpha": "0.7", "shear_rate": "0.03",
                 "theory": "exact", "Pxx_p": "1.01", "Pxx_p_ci": "0.005", "Pxx_p_theory": "1.02",
                 "Pxy_p": "-0.1", "Pxy_p_ci": "0.01", "Pxy_p_theory": "-0.1"}]
    blocks, verdict = COMPARE["shear_rheology"](name="shear_rheology", ours=rheology)
    assert verdict.kind == "differs" and "Pxx/p of λ = 0" in blocks[1][1][0]


def test_a_row_outside_both_sonine_intervals_says_so_and_the_elastic_limit_is_judged():
    rows = transport_table.complete_rows([transport_table.row("hard_spheres", 3, 0.5, "D", "green_kubo", 1.70, 0.006),
                                          transport_table.row("hard_spheres", 3, 1.0, "eta", "green_kubo", 1.017, 0.005),
                                          transport_table.row("hard_spheres", 3, 1.0, "kappa", "relaxation", 1.25, 0.09)])
    favoured, zs, zm = transport_table.sonine_preference(next(r for r in rows if r["alpha"] == 0.5))
    assert favoured == "modified, neither within" and zs < zm < -3.2
    ours, short, kind = transport_table.transport_verdict(rows)
    # each row counted once: closer to modified but outside both, and two whose versions coincide
    assert kind == "approximation" and ("hard spheres, 3 rows: 0 favour modified Sonine, 0 standard; 1 closer to "
                                        "modified but outside both, 0 closer to standard; 2 not resolved (2 of them "
                                        "outside both)") in short
    assert "eta* green_kubo 1.0170 ± 0.0050 vs the converged Chapman–Enskog 1.0160 (+0.6σ) and the first Sonine 1 (+10.9σ): resolved" in ours
    assert "kappa* relaxation" in ours and ours.endswith("differs")


def test_usf_rows_extrapolate_the_exact_maxwell_rheology_to_the_exact_eta():
    """Steady shear flow fed the exact lambda = 0 rheology at the profiles' rates a* = 0.03-0.09:
    the extrapolation must return the exact eta; through a^2 alone it falls 0.4 % short."""
    from granboltz.theory.shear import maxwell_gaussian_usf_ratios

    nu = 4 * math.pi  # |S^2| gamma C at gamma = C = 1
    runs = []
    for reduced in (0.03, 0.06, 0.09):
        a = reduced * nu
        P = maxwell_gaussian_usf_ratios(0.5, a, 1.0, 1.0)
        runs.append(types.SimpleNamespace(
            path=f"a{reduced}", steady={"pressure_tensor": types.SimpleNamespace(mean=P, ci=np.full((3, 3), 1e-3))},
            config={"dsmc": {"kernel": {"lambda": 0}, "alpha": 0.5, "thermostat": "gaussian", "shear": {"rate": a}}}))
    row = transport_table.complete_rows(transport_table.usf_rows(runs))[0]
    assert abs(row["value"] / row["exact"] - 1) < 1e-3, row
    biased = transport_table.complete_rows(transport_table.usf_rows(runs, order=2))[0]
    assert biased["value"] / biased["exact"] - 1 < -3e-3, biased
