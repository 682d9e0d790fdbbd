"""The shear_rheology table (granboltz.rheology): the exact rheology of Maxwell molecules is met
within the table's own intervals, with and without the Gaussian thermostat, in d = 3 and d = 2;
the Grad closure under the thermostat agrees with the free one where their states coincide; the
table's columns and refusals."""

import math

import numpy as np
import pytest

import granboltz
from granboltz.reproduction import rheology
from granboltz.theory import shear


def _run(lam, d=3, thermostat=None, rate=1.0, alpha=0.5, ensembles=16, particles=1000, t_end=30,
         seed=11):
    C = 1 / (4 * math.pi) if d == 3 else 1 / (2 * math.pi)  # nu = 1 for Maxwell molecules
    section = {"particles": particles, "alpha": alpha, "beta": 0, "gamma": 1, "dimension": d,
               "geometry": "uniform",
               "kernel": {"lambda": lam, "C": C}, "t_end": t_end, "observe_every": 0.5,
               "steady_from": min(10, t_end / 2), "shear": {"rate": rate}}
    if thermostat:
        section["thermostat"] = thermostat
    if thermostat == "gaussian" and lam != 0:  # the scale enters the hard-sphere rate
        section.update(scheme="strang", steps=int(20 * t_end))
    return granboltz.simulate({"model": "dsmc", "seed": seed, "ensembles": ensembles,
                               "dsmc": section}, progress=False)


def test_maxwell_rheology_is_met_within_the_tables_intervals():
    """[exact] Free at the steady shear rate a_s (d = 3; T constant, the conservative ratio
    interval) and under the Gaussian thermostat at a = nu/2 (d = 2; p held)."""
    a_s = shear.maxwell_steady_shear_rate(0.5, 1.0, 1 / (4 * math.pi))
    runs = [_run(0, rate=a_s), _run(0, d=2, thermostat="gaussian", rate=0.5, seed=12)]
    table = rheology.shear_rheology(runs)
    assert list(table.columns) == rheology.COLUMNS
    assert list(table["d"]) == [2, 3] and set(table["theory"]) == {"exact"}
    for _, row in table.iterrows():
        for name in ("xx", "yy", "zz", "xy"):
            if row["d"] == 2 and name == "zz":
                assert math.isnan(row["Pzz_p"]) and math.isnan(row["Pzz_p_theory"])
                continue
            value, ci, exact = row[f"P{name}_p"], row[f"P{name}_p_ci"], row[f"P{name}_p_theory"]
            assert ci > 0 and abs(value - exact) <= ci, (row["d"], name, value, ci, exact)
    # At a_s the exact free state is transport.md's closed form.
    free = table[table["d"] == 3].iloc[0]
    closed = shear.maxwell_usf_ratios(0.5)
    for name in ("xx", "yy", "zz", "xy"):
        assert free[f"P{name}_p_theory"] == pytest.approx(closed[name], abs=1e-9)
    assert free["shear_rate"] == pytest.approx(a_s)


def test_the_thermostatted_grad_closure_meets_the_free_one_at_its_steady_shear_rate():
    """[exact algebra] At the free gas's steady reduced shear rate the thermostat does no work,
    so the two closures give the same P/p; at small a* P_xy/p = -a*/(nu_eta* - zeta0*)."""
    C = 1 / (4 * math.pi)
    for alpha in (0.3, 0.6, 0.9):
        free = shear.hard_sphere_usf_grad(alpha, 1.0, 1.0, C)
        held = shear.hard_sphere_usf_grad_gaussian(alpha, free["reduced_shear_rate"])
        for name in ("xx", "yy", "zz", "xy"):
            assert held[name] == pytest.approx(free[name], abs=1e-9), (alpha, name)
        small = shear.hard_sphere_usf_grad_gaussian(alpha, 1e-4)
        nu = (3 - alpha) * (1 + alpha) / 4 - 5 / 12 * (1 - alpha * alpha)
        assert small["xy"] == pytest.approx(-1e-4 / nu, rel=1e-6)


def test_hard_sphere_rows_carry_the_grad_values_at_their_own_shear_rate():
    run = _run(1, thermostat="gaussian", rate=0.3, ensembles=10, particles=500, t_end=16)
    row = rheology.shear_rheology_row(run)
    T = row["temperature"]
    assert row["model"] == "hard_spheres" and row["theory"] == "grad"
    assert row["shear_rate"] == pytest.approx(0.3 / shear.hard_sphere_nu0(T, 1.0, 1 / (4 * math.pi)))
    grad = shear.hard_sphere_usf_grad_gaussian(0.5, row["shear_rate"])
    assert row["Pxy_p_theory"] == pytest.approx(grad["xy"])
    # p is held by the thermostat: the ratio's interval is the component's over p.
    P = run.steady["pressure_tensor"]
    assert row["Pxy_p_ci"] == pytest.approx(float(np.asarray(P.ci)[0, 1]) / (np.trace(P.mean) / 3))


def test_runs_the_table_cannot_take_are_refused_by_name():
    run = _run(0, rate=0.5, ensembles=2, particles=200, t_end=4)
    run.config["dsmc"]["shear"] = {}
    with pytest.raises(ValueError, match="no dsmc.shear.rate"):
        rheology.shear_rheology_row(run)
    run.config["dsmc"]["shear"] = {"rate": 0.5}
    run.config["dsmc"]["kernel"]["lambda"] = 0.5
    with pytest.raises(ValueError, match="dsmc.kernel.lambda = 0.5"):
        rheology.shear_rheology_row(run)
    # Disks with the impact law: no exact rheology here, the theory columns stay empty.
    run.config["dsmc"]["kernel"]["lambda"] = 0
    run.config["dsmc"].update(dimension=2, geometry="impact")
    import dataclasses
    P = run.steady["pressure_tensor"]
    run.steady["pressure_tensor"] = dataclasses.replace(P, mean=np.asarray(P.mean)[:2, :2])
    row = rheology.shear_rheology_row(run)
    assert row["theory"] == "" and math.isnan(row["Pxy_p_theory"])
