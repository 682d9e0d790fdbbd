"""The verdicts of the TV06 figure summaries (granboltz.reproduction.tv06_verdicts) on rows and
numbers with known answers: each agrees where they do and fails where a point is outside."""

import numpy as np

from granboltz.reproduction import tv06_verdicts as tv
from granboltz.theory import gaussian_temperature_ratio, t_coverage


def test_collision_rates_and_colliding_velocity_texts():
    ours, short = tv.collision_rates_verdict([0.5, 1.0], 1.0, (-3.0, 3.0), 2e-9, 1e-15, 3e-16, "t.csv")
    assert ours.startswith("eqs. (15)–(16) for a = 0.5, 1 (ρ = 1) on v1 ∈ [-3, 3]; on the grid of `t.csv` the closed "
                           "forms agree with quadrature of eqs. (5)–(6) to 2.0e-09")
    assert short == "analytic; closed forms = quadrature of eqs. (5)–(6) to 2e-09; φ(0) = ρ/√(πa)"
    ours, short = tv.colliding_velocity_verdict([-1.0, 0.5], 1.0, 1.0, 3e-12, {"-1": 1e-3, "0.5": 2e-4})
    assert ours.startswith("eq. (12) for v1 = -1, 0.5 (a = 1, ρ = 1; the paper does not state a)")
    assert ours.endswith("leave out the mass 1.0e-03 (v1 = -1), 2.0e-04 (v1 = 0.5)")
    assert short == "analytic; ∫g+ dv = 1 within 3e-12; no simulator histogram (not an output)"


def _temperature_rows(z):
    return [{"M": 1.0, "alpha": a, "N": 100, "collisions": 10000, "within_ci": "yes" if abs(zz) <= 3.2 else "no",
             "z": zz, "deviation": 1e-4 * zz} for a, zz in zip((0.2, 0.6, 1.0), z)]


def test_temperature_ratio_counts_the_points_inside():
    ok, ours, short, numbers = tv.temperature_ratio_verdict(_temperature_rows([0.5, -2.0, 1.0]), "t.csv")
    assert ok and short == "agrees: 3/3 points within the CI of eq. (18) (max 2.0σ)"
    assert ours.startswith("3/3 points within their 99.9 % confidence interval of eq. (18) (N = 100 ensembles × "
                           "10000 collisions per point; largest deviation -0.00020 = -2.0σ at α = 0.6)")
    assert numbers == {"inside": 3, "points": 3, "max_abs_z": 2.0, "coverage_per_point": t_coverage(100)}
    ok, ours, short, numbers = tv.temperature_ratio_verdict(_temperature_rows([0.5, -4.0, 1.0]), "t.csv")
    assert not ok and short == "1 point(s) outside: 2/3 points within the CI of eq. (18) (max 4.0σ)"


def test_powerlaw_temperature_against_the_gaussian_curve():
    rows = [{"M": 0.5, "alpha": a, "T_ratio": float(gaussian_temperature_ratio(a, 0.5)) * f, "ci": 0.01,
             "exact": 0.5 if a == 0.5 else None, "z": -1.2 if a == 0.5 else 0.0, "N": 50, "collisions": 1000}
            for a, f in ((0.2, 1.3), (0.5, 1.0), (0.9, 1.02))]
    ours, short = tv.powerlaw_temperature_verdict(rows, "t.csv")
    assert short == ("M = 0.5: within 2.0 % of eq. (18) for α > M; M = α = 0.5: -1.2 nominal σ (σ from nominal CIs, "
                     "indicative: infinite variance)")
    assert ours.startswith("exact at M = α = 0.5: ")
    assert "M = 0.5: within 2.0 % of the Gaussian curve for α > M, up to 30 % above it for α < M (N = 50" in ours
    assert ours.endswith("Numbers: `t.csv`")


def test_powerlaw_distribution_exponents_peaks_and_check():
    fits = {"0.2": {"exponent": -3.9, "stderr": 0.1}, "0.5": {"exponent": -4.1, "stderr": 0.1}}
    check = {"alpha": 0.5, "within": 58, "bins": 60, "max_z": 3.6}
    ours, short = tv.powerlaw_distribution_verdict(fits, [0.5, 0.4], check, [3, 30], 100, "t.csv")
    assert short == "tail exponents -4.10 … -3.90 (theory −4); α = M: 58/60 bins within CI of the exact f"
    assert "the peak falls monotonically as α grows" in ours and ours.endswith(". Numbers: `t.csv`")
    ours, short = tv.powerlaw_distribution_verdict(fits, [0.4, 0.5], None, [3, 30], 100, "t.csv")
    assert "does not fall monotonically with α: 0.400, 0.500" in ours and "α = M" not in short


def _needle_rows(R_z_elastic, ordering):
    rows = []
    for M in (0.1, 1.0):
        rows.append({"M": M, "alpha": 0.1, "R": 1.3 - 0.1 * M, "R_ci": 0.01, "R_exact": None, "R_z": None,
                     "ordering": ordering, "T_trans": 0.6, "T_rot": 0.4, "N": 20, "collisions": 1000})
        rows.append({"M": M, "alpha": 1.0, "R": 1.0, "R_ci": 0.01, "R_exact": 1.0, "R_z": R_z_elastic,
                     "ordering": "equipartition", "T_trans": 1.0, "T_rot": 1.0, "N": 20, "collisions": 1000})
    return rows


def test_needle_correlation_needs_every_check():
    ok, ours, short, numbers = tv.needle_correlation_verdict(_needle_rows(0.5, "T_B > T_trans > T_rot"), "t.csv")
    assert ok and short == ("agrees: R = 1 within CI at α = 1 (2/2); T_B > T_trans > T_rot at 2/2 points with α < 1")
    assert ours.startswith("R at α = 0.1: 1.2900 ± 0.0100 (M = 0.1), 1.2000 ± 0.0100 (M = 1) — above 1 and decreasing")
    assert numbers == {"R_elastic_ok": 2, "ordered": 2, "inelastic": 2, "equipartition": 2,
                       "R_low_alpha": {"0.1": 1.29, "1": 1.2}}
    ok, _, short, _ = tv.needle_correlation_verdict(_needle_rows(4.0, "T_B > T_trans > T_rot"), "t.csv")
    assert not ok and short.startswith("check: R = 1 within CI at α = 1 (0/2)")
    ok, _, short, _ = tv.needle_correlation_verdict(_needle_rows(0.5, "unresolved"), "t.csv")
    assert not ok and short.endswith("at 0/2 points with α < 1")


def test_needle_omega_deviations_resolved_by_the_binomial_count():
    run = {"M": 0.1, "alpha": 0.1, "N": 100, "collisions": 50000, "config": {"length": 1.0}}
    fit = {"s_fit": 0.5, "s_moments": 0.52, "excess_kurtosis": 0.21}
    ci = np.r_[np.full(100, 0.01), 0.0]
    resolved, ours, short, numbers = tv.needle_omega_verdict(run, fit, np.r_[np.full(100, 0.5), 9.0], ci, "t.csv")
    assert not resolved and short == ("deviations from the best-fit Gaussian not resolved: outside the CI at 0/100 "
                                      "bins; excess kurtosis +0.210")
    assert ours.startswith("M = 0.1, α = 0.1, N = 100 × 50000 = 5,000,000 collisions (L = 1, a = 1)")
    assert numbers == {"s_fit": 0.5, "s_moments": 0.52, "excess_kurtosis": 0.21, "bins_outside": 0, "bins": 100}
    z = np.r_[np.full(20, 5.0), np.full(80, 0.5), 0.0]  # 20 of 100 bins miss: far beyond the expected 0.1-0.2
    resolved, ours, short, numbers = tv.needle_omega_verdict(run, fit, z, ci, "t.csv")
    assert resolved and short.startswith("deviations from the best-fit Gaussian resolved: outside the CI at 20/100")
