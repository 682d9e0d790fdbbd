"""The package's basics: analytic formulas, GRW05 Table 1 numbers, atomic files."""

import math
import os

import numpy as np
import pytest

from granboltz.reproduction.dsmc import read_dsmc
from granboltz.output.files import atomic_path, write_csv
from granboltz.reproduction.tables import convergence_rows
from granboltz.theory import analytic_temperature
from conftest import eq34


def test_analytic_temperature_is_eq34_for_example3():
    t = np.linspace(0.0, 8.0, 33)
    T = analytic_temperature(t, 1.0, 0.5, 1.0, 4.0, 1 / (4 * math.pi))
    np.testing.assert_allclose(T, eq34(t), rtol=1e-14)


def test_analytic_temperature_solves_the_moment_equation():
    # dT/dt = -k T + 2 beta with k = gamma pi C0 (1 - alpha^2) (GRW05 §2), T(0) = T0
    alpha, beta, gamma, C0, T0 = 0.3, 0.125, 2.0, 0.2, 1.7
    k = gamma * math.pi * C0 * (1 - alpha**2)
    t, h = np.linspace(0.1, 3.0, 30), 1e-6
    T = lambda s: analytic_temperature(s, T0, alpha, beta, gamma, C0)  # noqa: E731
    np.testing.assert_allclose((T(t + h) - T(t - h)) / (2 * h), -k * T(t) + 2 * beta, rtol=1e-7)
    assert T(0.0) == pytest.approx(T0)
    assert T(1e4) == pytest.approx(2 * beta / k)


def test_analytic_temperature_elastic_limit_grows_linearly():
    assert analytic_temperature(2.0, 1.0, 1.0, 0.5, 4.0, 0.1) == pytest.approx(3.0)


def test_convergence_rows_give_known_errors_factors_and_bulk_velocity(fake_run):
    V = np.zeros((33, 3))
    V[5] = [0.003, 0.004, 0.0]  # |V| = 0.005 at t = 1.25
    V[9] = [0.0, -0.001, 0.0]
    runs = [
        read_dsmc(fake_run(256, eps=0.02, eps_centred=-0.004, peak=12)),
        read_dsmc(fake_run(64, eps=0.08, eps_centred=0.016, peak=7, V=V, N=50)),
        read_dsmc(fake_run(1024, eps=-0.004, eps_centred=0.002, peak=32)),
    ]
    rows = convergence_rows(runs)
    assert [r["n"] for r in rows] == [64, 256, 1024]
    assert [r["N"] for r in rows] == [50, 100, 100]
    np.testing.assert_allclose([r["E_max"] for r in rows], [0.08, 0.02, 0.004], rtol=1e-12)
    assert rows[0]["CF"] is None and rows[0]["CF_centred"] is None
    np.testing.assert_allclose([r["CF"] for r in rows[1:]], [4.0, 5.0], rtol=1e-12)
    np.testing.assert_allclose([r["E_max_centred"] for r in rows], [0.016, 0.004, 0.002], rtol=1e-12)
    np.testing.assert_allclose([r["CF_centred"] for r in rows[1:]], [4.0, 2.0], rtol=1e-12)
    assert rows[0]["V_inf"] == pytest.approx(0.005, rel=1e-12)
    assert rows[1]["V_inf"] == 0.0
    assert [r["t_Emax"] for r in rows] == [1.75, 3.0, 8.0]
    # ci = 0.01 T(t) in the fake files: the relative half-width is 0.01 at any time
    np.testing.assert_allclose([r["E_max_ci"] for r in rows] + [r["Conf_end"] for r in rows], 0.01)


def test_convergence_rows_refuse_non_maxwell_kernels_and_repeated_n(fake_run):
    with pytest.raises(ValueError, match="lambda"):
        convergence_rows([read_dsmc(fake_run(64, kernel_lambda=1))])
    run = read_dsmc(fake_run(64))
    with pytest.raises(ValueError, match="same n"):
        convergence_rows([run, run])


def test_read_run_refuses_non_finite_data(fake_run):
    V = np.zeros((33, 3))
    V[3, 0] = np.nan
    with pytest.raises(ValueError, match="bulk_velocity/mean"):
        read_dsmc(fake_run(64, V=V))


def test_atomic_path_leaves_nothing_behind_on_failure(tmp_path):
    target = tmp_path / "out.csv"
    with pytest.raises(RuntimeError):
        with atomic_path(str(target)) as tmp:
            with open(tmp, "w") as out:
                out.write("half")
            raise RuntimeError("step failed")
    assert os.listdir(tmp_path) == []
    with atomic_path(str(target)) as tmp:
        with open(tmp, "w") as out:
            out.write("whole")
    assert target.read_text() == "whole" and os.listdir(tmp_path) == ["out.csv"]


def test_write_csv_formats_cells(tmp_path):
    path = tmp_path / "t.csv"
    write_csv([{"n": 64, "E": 0.0123456, "CF": None}], ["n", "E", "CF"], str(path))
    assert path.read_text() == "n,E,CF\n64,0.01235,\n"
