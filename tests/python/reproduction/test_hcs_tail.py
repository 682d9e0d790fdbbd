"""granboltz.reproduction.hcs_tail and its report comparison: the HCS tail theory A = 8 pi gamma C v0/zeta, the
fits of b and A on histograms with a known exponential tail, and the verdicts."""

import math

import numpy as np
import pytest

from granboltz.reproduction.hcs_tail import (HCS_TAIL_COLUMNS, hcs_amplitude, hcs_tail_row_verdict, hcs_tail_summary,
                                maxwellian_cooling_rate, sonine_cooling_rate, thermal_speed)
from granboltz.report.hcs_tail import compare_beyond_hcs_tail_swpm

GAMMA, C, T0 = 1.0, 1 / (4 * math.pi), 1.0
LOCAL = {"pool_min_count": 400, "tail_from": 1e-5}


def shells_of(density, R=20.0, K=40, rel=0.02, N=48):
    """Shells whose fractions follow `density` exactly, each with the relative standard error `rel`
    (as weighted particles give, about the same far out as in the core) and the counts of that
    precision."""
    edges = np.linspace(0.0, R, K + 1)
    r = 0.5 * (edges[1:] + edges[:-1])
    frac = density(r) * 4 * np.pi / 3 * (edges[1:] ** 3 - edges[:-1] ** 3)
    frac /= frac.sum()
    counts = np.full(K, int(1 / rel**2), dtype=np.int64)
    return {"edges": edges, "frac": frac, "se": rel * frac, "counts": counts, "N": N, "n": 1000}


def hcs_like(A, chi=0.0, r0=1.0):
    """A smooth core and the tail c^chi exp(-A c), c = r/v0 (f(0) = 1)."""
    v0 = thermal_speed(T0)
    return lambda r: (np.sqrt(r**2 + r0**2) / r0) ** chi * np.exp(-A * (np.sqrt(r**2 + r0**2) - r0) / v0)


def test_theory_amplitude_with_the_maxwellian_cooling_rate_is_3_sqrt_pi_over_2_over_1_minus_alpha2():
    for alpha in (0.3, 0.5, 0.8):
        zeta = maxwellian_cooling_rate(alpha, GAMMA, C, T0)
        assert hcs_amplitude(zeta, GAMMA, C, T0) == pytest.approx(3 * math.sqrt(math.pi / 2) / (1 - alpha**2), rel=1e-14)
    assert 3 * math.sqrt(math.pi / 2) == pytest.approx(3.7599, abs=1e-4)
    # in these units zeta_M = 4 (1 - alpha^2)/(3 sqrt(pi)); a2 = 0 at alpha = 1/sqrt(2)
    assert maxwellian_cooling_rate(0.5, GAMMA, C, T0) == pytest.approx(4 * 0.75 / (3 * math.sqrt(math.pi)), rel=1e-14)
    a = 1 / math.sqrt(2)
    assert sonine_cooling_rate(a, GAMMA, C, T0) == pytest.approx(maxwellian_cooling_rate(a, GAMMA, C, T0), rel=1e-14)
    # a2(1/2) = 4/76.25: zeta = zeta_M (1 + 3 a2/16), the value the C++ test holds the SWPM run to
    assert sonine_cooling_rate(0.5, GAMMA, C, T0) == pytest.approx(0.56419 * (1 + 3 * (4 / 76.25) / 16), rel=1e-4)
    # hard disks: 4 pi instead of 8 pi
    assert hcs_amplitude(1.0, GAMMA, C, T0, d=2) == pytest.approx(0.5 * hcs_amplitude(1.0, GAMMA, C, T0))


@pytest.mark.parametrize("alpha", [0.3, 0.5])
def test_summary_recovers_b_and_A_of_an_exponential_tail(alpha):
    zeta = sonine_cooling_rate(alpha, GAMMA, C, T0)
    A = hcs_amplitude(zeta, GAMMA, C, T0)
    s = hcs_tail_summary(shells_of(hcs_like(A)), alpha, zeta, GAMMA, C, T0, LOCAL)
    assert list(s)[: len(HCS_TAIL_COLUMNS)] == HCS_TAIL_COLUMNS
    assert s["A_theory"] == pytest.approx(A, rel=1e-14)
    assert s["b_swpm"] == pytest.approx(1.0, abs=0.01)
    assert s["A_swpm"] == pytest.approx(A, rel=0.01)
    assert s["chi_swpm"] == pytest.approx(0.0, abs=0.5)  # the core's r0^2/(2r) in the exponent leaks into chi
    assert s["depth_swpm"] < 1e-20
    assert hcs_tail_row_verdict(s)[0]


def test_the_amplitude_fit_takes_a_power_prefactor_and_the_verdict_sees_a_wrong_zeta():
    A = 5.0
    zeta = 8 * math.pi * GAMMA * C * thermal_speed(T0) / A
    s = hcs_tail_summary(shells_of(hcs_like(A, chi=2.0)), 0.5, zeta, GAMMA, C, T0, LOCAL)
    assert s["A_swpm"] == pytest.approx(A, rel=0.02) and s["chi_swpm"] == pytest.approx(2.0, abs=0.5)
    # the same histogram against a cooling rate 10 % off: A_theory moves, the verdict says differs
    bad = hcs_tail_summary(shells_of(hcs_like(A)), 0.5, 1.1 * zeta, GAMMA, C, T0, LOCAL)
    ok, text = hcs_tail_row_verdict(bad)
    assert not ok and "%" in text
    # a Gaussian tail is not exponential: b far from 1
    g = hcs_tail_summary(shells_of(lambda r: np.exp(-r**2 / 2), R=9.0, K=36), 0.5, zeta, GAMMA, C, T0, LOCAL)
    assert g["b_swpm"] > 1.5 and not hcs_tail_row_verdict(g)[0]


def test_a_histogram_without_a_resolved_tail_gives_nan_and_differs():
    s = shells_of(hcs_like(5.0), rel=0.2)
    row = hcs_tail_summary(s, 0.5, 0.57, GAMMA, C, T0, LOCAL)
    assert not row["depth_swpm"] <= 1e-20  # nan: no shell resolved
    assert not hcs_tail_row_verdict(row)[0]


def _row(alpha=0.5, b=1.005, b_ci=0.02, A=5.02, At=4.97, depth=1e-21):
    return {"alpha": str(alpha), "b_swpm": str(b), "b_swpm_ci": str(b_ci), "A_swpm": str(A), "A_theory": str(At),
            "depth_swpm": str(depth)}


def test_compare_agrees_only_when_every_row_meets_the_targets():
    blocks, short = compare_beyond_hcs_tail_swpm("beyond_hcs_tail", [_row(), _row(alpha=0.3, A=4.05, At=4.05)])
    assert short.kind == "agrees" and short.startswith("agrees") and len(blocks[0][2]) == 2
    # resolved rows that miss b or A differ from the exact asymptotics; only they are named
    for bad, what in ((_row(b=1.05), "b = 1.050"), (_row(A=5.4), "+8.7 %")):
        blocks, short = compare_beyond_hcs_tail_swpm("beyond_hcs_tail", [_row(alpha=0.3), bad])
        assert short.kind == "differs" and short.startswith("differs") and what in short, short
        assert "α = 0.3" not in short
        assert blocks[0][2][1][-1] == "differs" and blocks[0][2][0][-1] == "agrees"
    # a shallow or unresolved row judges nothing: the run is too small, not wrong
    for shallow, what in ((_row(depth=1e-15), "depth 1.0e-15"), (_row(b="nan", A="nan"), "b = nan"),
                          (_row(b=1.3, b_ci=0.5), "b = 1.300")):
        _, short = compare_beyond_hcs_tail_swpm("beyond_hcs_tail", [shallow])
        assert short.kind == "approximation" and short.startswith("not resolved") and what in short, short
        _, short = compare_beyond_hcs_tail_swpm("beyond_hcs_tail", [_row(alpha=0.3), shallow])
        assert short.kind == "agrees" and "not resolved: α = 0.5" in short and what in short, short
    assert compare_beyond_hcs_tail_swpm("beyond_hcs_tail", [])[1].kind == "approximation"
