"""The numbers of the RW05 tables, the effort model and the GRW05 tail fits
(the granboltz package), on synthetic inputs with known answers."""

import math

import numpy as np
import pytest

from granboltz.reproduction.dsmc import crit_of_means, read_dsmc, read_histogram, read_steady
from granboltz.reproduction.steady import effort_rows, replica_rows, STEADY_COLUMNS, steady_rows
from granboltz.reproduction.tables import fit_order, RW05_TABLE1_COLUMNS, rw05_table1_rows, timestep_rows
from granboltz.analysis.tails import fit_tail, TAIL_COLUMNS, tail_points, tail_rows, WINDOW_COLUMNS
from granboltz.theory import expected_error, scheme_steady_temperature, scheme_temperature
from conftest import (ROOT, add_moments, tail_histogram, write_fake_histogram_run, write_fake_run,
                      write_fake_scheme_run, write_fake_steady_run)

K_EX = 0.75  # k = gamma pi C0 (1 - alpha^2) of RW05 §4 and GRW05 Example 3


# ----------------------------------------------------------------------------- analytic formulas
@pytest.mark.parametrize("scheme", ["euler", "strang"])
def test_scheme_temperature_is_the_step_recurrence(scheme):
    dt, T, out = 0.5, 1.0, [1.0]
    for _ in range(16):
        T = math.exp(-K_EX * dt) * T + 2 * dt if scheme == "euler" else \
            math.exp(-K_EX * dt / 2) * (math.exp(-K_EX * dt / 2) * T + 2 * dt)
        out.append(T)
    t = np.arange(17) * dt
    np.testing.assert_allclose(scheme_temperature(scheme, t, dt, 1.0, 0.5, 1.0, 1.0, 1 / np.pi), out, rtol=1e-13)
    assert scheme_steady_temperature(scheme, dt, 0.5, 1.0, 1.0, 1 / np.pi) == pytest.approx(
        scheme_temperature(scheme, [400.0], dt, 1.0, 0.5, 1.0, 1.0, 1 / np.pi)[0], rel=1e-12)


def test_steady_temperatures_of_rw05():
    # T_inf = 8/3 (eq. 25); Euler K = 32: 2 beta dt / (1 - e^{-k dt}) = 2.9245; Strang: times e^{-k dt/2}
    assert scheme_steady_temperature("nosplit", None, 0.5, 1.0, 1.0, 1 / np.pi) == pytest.approx(8 / 3)
    assert scheme_steady_temperature("euler", 0.25, 0.5, 1.0, 1.0, 1 / np.pi) == pytest.approx(2.924475, abs=1e-5)
    assert scheme_steady_temperature("strang", 0.25, 0.5, 1.0, 1.0, 1 / np.pi) == pytest.approx(
        2.924475 * math.exp(-0.09375), abs=1e-5)
    with pytest.raises(ValueError, match="multiples"):
        scheme_temperature("euler", [0.3], 0.25, 1.0, 0.5, 1.0, 1.0, 1 / np.pi)


def test_expected_error_is_the_exact_bias_of_the_uncentred_estimator(tmp_path):
    run = read_dsmc(write_fake_run(tmp_path / "r.h5", 64))
    t = run.time
    T = np.exp(-0.75 * t) + 8 / 3 * (1 - np.exp(-0.75 * t))
    bias = np.abs((1 + 2 * t) - T) / (64 * T)  # ((T0 + 2 beta t) - T(t)) / n, relative
    assert expected_error(run) == pytest.approx((bias.max(), bias[-1]), rel=1e-12)
    assert 64 * bias.max() == pytest.approx(5.385, abs=1e-3)  # the published E_max is about 5.7/n


def test_fit_order_recovers_the_exponent():
    n = np.array([64, 256, 1024, 4096])
    p, se = fit_order(n, 3.0 * n ** -1.0)
    assert p == pytest.approx(1.0) and se == pytest.approx(0.0, abs=1e-12)
    assert fit_order([4, 8], [1.0, 0.25])[0] == pytest.approx(2.0) and math.isnan(fit_order([4, 8], [1, 0.25])[1])


# ----------------------------------------------------------------------------- RW05 Tables 1, 2
def test_rw05_table1_rows(tmp_path):
    runs = [read_dsmc(write_fake_run(tmp_path / f"{n}.h5", n, eps=e, peak=10)) for n, e in ((16, 0.4), (64, 0.1))]
    rows = rw05_table1_rows(runs)
    assert [r["n"] for r in rows] == [16, 64]
    np.testing.assert_allclose([r["E_max"] for r in rows], [0.4, 0.1])
    np.testing.assert_allclose([r["E_end"] for r in rows], [0.2, 0.05])  # eps/2 away from the peak
    assert rows[1]["CF_E_max"] == pytest.approx(4.0) and rows[1]["CF_E_end"] == pytest.approx(4.0)
    assert rows[0]["Conf_end"] == pytest.approx(0.01) and rows[1]["CF_Conf_end"] == pytest.approx(1.0)
    assert rows[0]["T_end_exact"] == pytest.approx(8 / 3 - 5 / 3 * math.exp(-6))
    assert set(RW05_TABLE1_COLUMNS) <= set(rows[0])


def test_timestep_rows_give_the_scheme_errors_and_first_and_second_order(tmp_path):
    euler = [read_dsmc(write_fake_scheme_run(tmp_path / f"e{K}.h5", 4096, "euler", K)) for K in (4, 8, 16, 32)]
    strang = [read_dsmc(write_fake_scheme_run(tmp_path / f"s{K}.h5", 4096, "strang", K)) for K in (32, 16, 8, 4)]
    rows = timestep_rows(euler, strang, 8.0)
    assert [r["K"] for r in rows] == [4, 8, 16, 32]
    # the fake runs are the expectations: E_max = E_expected; the published K = 4 values are 0.931, 0.0863
    for r in rows:
        assert r["E_max_euler"] == pytest.approx(r["E_expected_euler"], rel=1e-9)
        assert r["E_max_strang"] == pytest.approx(r["E_expected_strang"], rel=1e-9)
    assert rows[0]["E_max_euler"] == pytest.approx(0.931, abs=5e-4)
    assert rows[0]["E_max_strang"] == pytest.approx(0.0866, abs=5e-4)
    assert fit_order([r["K"] for r in rows], [r["E_max_euler"] for r in rows])[0] == pytest.approx(1.0, abs=0.12)
    assert fit_order([r["K"] for r in rows[:3]], [r["E_max_strang"] for r in rows[:3]])[0] == pytest.approx(
        2.0, abs=0.12)
    with pytest.raises(ValueError, match="strang"):
        timestep_rows(euler, strang[:3], 8.0)


# ----------------------------------------------------------------------------- RW05 Tables 3-6
def steady(tmp_path, name, **kwargs):
    return read_steady(write_fake_steady_run(tmp_path / f"{name}.h5", 65536, **kwargs))


def test_steady_rows_give_error_conf_cpu_and_factors(tmp_path):
    nosplit = steady(tmp_path, "n", T_inf=2.6684, ci=0.004, wall=2.0)
    runs = [steady(tmp_path, f"e{K}", scheme="euler", K=K, T_inf=8 / 3 + err, ci=0.005, wall=w)
            for K, err, w in ((256, 0.03, 13.0), (32, 0.24, 2.2), (512, 0.015, 26.0))]
    rows = steady_rows(runs, nosplit, 8.0)
    assert [r["K"] for r in rows] == [32, 256, 512]
    np.testing.assert_allclose([r["Error"] for r in rows], [0.24, 0.03, 0.015], rtol=1e-9)
    assert rows[0]["CF_Error"] is None
    np.testing.assert_allclose([r["CF_Error"] for r in rows[1:]], [8.0, 2.0], rtol=1e-9)
    np.testing.assert_allclose([r["CPU"] for r in rows], [1.1, 6.5, 13.0])
    np.testing.assert_allclose([r["CF_CPU"] for r in rows[1:]], [6.5 / 1.1, 2.0])
    assert [r["Conf"] for r in rows] == [0.005] * 3 and rows[0]["dt"] == 0.25 and rows[0]["samples"] == 64
    assert rows[0]["T_scheme"] == pytest.approx(2.924475, abs=1e-5)
    # T_expected adds the finite-n bias of |v|^2/3: mean over t_m > 8 of (1 + 2 t)/n, minus T/n
    assert rows[0]["T_expected"] == pytest.approx(rows[0]["T_scheme"] * (1 - 1 / 65536) + 147 / 65536, rel=1e-12)
    (single,) = steady_rows([nosplit], nosplit, 8.0)
    assert single["CPU"] == 1.0 and single["K"] is None and single["Error"] == pytest.approx(2.6684 - 8 / 3, rel=1e-9)
    assert set(STEADY_COLUMNS["steps"]) <= set(rows[0])


def test_steady_rows_put_the_batch_interval_beside_conf(tmp_path):
    nosplit = steady(tmp_path, "n", ci=0.004, batch=(0.011, 0.0028, 1.7))
    (row,) = steady_rows([nosplit], nosplit, 8.0)
    assert row["Conf"] == 0.004 and row["Conf_batch"] == 0.011 and row["tau_int"] == 1.7
    for layout, table in (("steps", "rw05_table3_euler"), ("single", "rw05_table5_nosplit"), ("methods", "rw05_table6")):
        published = (ROOT / "config" / "published" / f"{table}.csv").read_text().splitlines()[0].split(",")
        assert STEADY_COLUMNS[layout][len(published):][:2] == ["Conf_batch", "tau_int"]  # ours, after the paper's
    (old,) = steady_rows([steady(tmp_path, "o")], nosplit, 8.0)  # a file without it: an empty cell
    assert old["Conf_batch"] is None and old["tau_int"] is None


def test_steady_rows_of_table6_use_t_inf_100(tmp_path):
    runs = [steady(tmp_path, "h", beta=37.5, T_inf=109.596, scheme="euler", K=32)]
    (row,) = steady_rows(runs, runs[0] | {"wall_seconds": 1.0}, 8.0)
    assert row["T_exact"] == pytest.approx(100.0) and row["Error"] == pytest.approx(9.596)
    assert row["Error_percent"] == pytest.approx(9.596) and row["T_scheme"] == pytest.approx(109.668, abs=1e-3)


def test_effort_rows_follow_the_model_of_rw05(tmp_path):
    n, s_M = 65536, 136.0
    n_coll = 2 * (n - 1) * s_M
    runs = [steady(tmp_path, "n", events=(n_coll, 0, 2 * n_coll + 68 * n), wall=1.0),
            steady(tmp_path, "e", scheme="euler", K=32, events=(n_coll, 0, s_M * n / 0.25), wall=0.9)]
    rows = effort_rows(runs, 8.0, 8.0)
    nosplit, euler = rows
    assert nosplit["N_coll_model"] == round(n_coll) and nosplit["M"] == 64 and nosplit["observations"] == 68
    assert nosplit["N_kick_model"] == round(2 * n_coll + 64 * n)  # as printed: n M
    assert nosplit["N_kick_model_grid"] == round(2 * n_coll + 68 * n) and nosplit["kick_ratio"] == pytest.approx(1.0)
    assert euler["N_kick_model"] == 544 * n and euler["K"] == 32 and euler["CPU"] == pytest.approx(0.9)
    # equal effort near dt = 1/4 (RW05: 1/dt ~ 4 + 1/dt_max)
    assert euler["effort_rel_model"] == pytest.approx((n_coll + 544 * n) / (3 * n_coll + 68 * n))
    with pytest.raises(ValueError, match="no-splitting"):
        effort_rows(runs[1:], 8.0, 8.0)


def test_replica_rows_measure_the_spread_against_the_nominal_sigma(tmp_path):
    T = [2.667, 2.671, 2.663, 2.669]
    runs = [steady(tmp_path, f"r{i}", T_inf=t, ci=3.2 * 0.002) for i, t in enumerate(T)]
    (row,) = replica_rows([runs], 8.0)
    assert row["replicas"] == 4 and row["T_inf_mean"] == pytest.approx(np.mean(T))
    assert row["T_inf_sd"] == pytest.approx(np.std(T, ddof=1)) and row["sigma_nominal"] == pytest.approx(0.002)
    assert row["sd_ratio"] == pytest.approx(np.std(T, ddof=1) / 0.002)
    assert row["z_expected"] == pytest.approx((np.mean(T) - row["T_expected"]) / (np.std(T, ddof=1) / 2))
    assert row["sigma_batch"] is None and row["sd_ratio_batch"] is None  # files without the batch interval


def test_replica_rows_measure_the_spread_against_the_batch_sigma_too(tmp_path):
    T, sigmas = [2.667, 2.671, 2.663, 2.669], [0.003, 0.004, 0.002, 0.005]
    runs = [steady(tmp_path, f"r{i}", T_inf=t, ci=3.2 * 0.002, batch=(4 * s, s)) for i, (t, s) in enumerate(zip(T, sigmas))]
    (row,) = replica_rows([runs], 8.0)
    rms = np.sqrt(np.mean(np.square(sigmas)))  # each run's sigma^2 estimates the variance
    assert row["sigma_batch"] == pytest.approx(rms) and row["sd_ratio_batch"] == pytest.approx(np.std(T, ddof=1) / rms)
    assert row["sd_ratio"] == pytest.approx(np.std(T, ddof=1) / 0.002)


# ----------------------------------------------------------------------------- Crit, eq. (29)
def test_crit_of_means_vanishes_for_a_maxwellian_and_has_the_right_scale(tmp_path):
    run = read_dsmc(add_moments(write_fake_run(tmp_path / "r.h5", 256), crit_value=0.0))
    np.testing.assert_allclose(crit_of_means(run)[0], 0.0, atol=1e-15)
    run = read_dsmc(add_moments(write_fake_run(tmp_path / "s.h5", 256), crit_value=0.12))
    crit, ci = crit_of_means(run)
    np.testing.assert_allclose(crit, 0.12, rtol=1e-12)
    np.testing.assert_allclose(ci, 0.01, rtol=1e-12)


# ----------------------------------------------------------------------------- GRW05 tails, eq. (38)
@pytest.mark.parametrize("b", [1.0, 1.25, 1.5])
def test_exact_histogram_gives_b_and_intercept(b):
    edges, mean, counts = tail_histogram(a=0.5, b=b)
    hist = {"edges": edges, "mean": mean[None], "counts": counts[None]}
    k, x, y = tail_points(hist, 1, 1)
    fit = fit_tail(x, y, [1.0, 3.0])
    h = 40.0 / 128
    assert fit["b"] == pytest.approx(b, rel=1e-9) and fit["b_stderr"] < 1e-8
    assert fit["intercept"] == pytest.approx(math.log(0.5) + b * math.log(h), abs=1e-8)
    np.testing.assert_allclose(x, np.log(k - 1))


@pytest.mark.parametrize("b,window", [(1.0, [2.5, 3.5]), (1.5, [2.0, 3.0])])
def test_sampled_histogram_gives_b_within_its_standard_error(b, window):
    edges, mean, counts = tail_histogram(a=0.5, b=b, total=10**8, seed=7)
    hist = {"edges": edges, "mean": mean[None], "counts": counts[None]}
    _, x, y = tail_points(hist, 1, 1)
    fit = fit_tail(x, y, window)
    assert fit["points"] >= 10 and 0 < fit["b_stderr"] < 0.05
    assert abs(fit["b"] - b) < 3 * fit["b_stderr"]


def test_tail_points_skip_empty_shells_and_refuse_an_empty_reference():
    edges, mean, counts = tail_histogram(a=0.5, b=1.0)
    counts, mean = counts.copy(), mean.copy()
    mean[[40, 41]], counts[[40, 41]] = 0.0, 0
    k, x, y = tail_points({"edges": edges, "mean": mean[None], "counts": counts[None]}, 1, 1)
    assert 41 not in k and 42 not in k and np.all(np.isfinite(y))
    mean[0], counts[0] = 0.0, 0
    with pytest.raises(ValueError, match="k0 = 1"):
        tail_points({"edges": edges, "mean": mean[None], "counts": counts[None]}, 1, 1)


def test_raw_fractions_leave_y_undefined_below_the_crossing():
    edges, mean, counts = tail_histogram(a=0.5, b=1.0)
    hist = {"edges": edges, "mean": mean[None], "counts": counts[None]}
    k_frac, _, _ = tail_points(hist, 1, 1, histogram="fraction")
    k_dens, _, _ = tail_points(hist, 1, 1, histogram="density")
    assert k_frac.min() > 10 and k_dens.min() == 2


def test_tail_rows_make_the_exponent_and_window_tables(tmp_path):
    hists = {ex: read_histogram(write_fake_histogram_run(tmp_path / f"{ex}.h5", lam=lam, b=1 + lam / 2))
             for ex, lam in ((7, 0.0), (8, 1.0), (9, 0.5))}
    tails = {"k0": 1, "min_count": 1, "histogram": "density", "fit_window": [2.0, 3.0],
             "windows": [[1.0, 2.0], [2.0, 3.0]]}
    rows, wrows = tail_rows(hists, tails)
    assert [r["kernel"] for r in rows] == ["maxwell", "hard_spheres", "vhs"]
    np.testing.assert_allclose([r["b"] for r in rows], [1.0, 1.5, 1.25], rtol=1e-9)
    np.testing.assert_allclose([r["theory_b"] for r in rows], [1.0, 1.5, 1.25])
    assert rows[0]["fit_window"] == "[2, 3]" and rows[0]["x_variable"] == "ln(k-k0)"
    assert len(wrows) == 3 * 2 * 2 and wrows[0]["k_minus_k0"] == "3-7"  # e^1 .. e^2
    assert set(TAIL_COLUMNS) <= set(rows[0]) and set(WINDOW_COLUMNS) <= set(wrows[0])
