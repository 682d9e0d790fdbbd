"""granboltz.analysis.tail_swpm: f(0) from the core, the resolved depth, effective counts, the
asymptotic b and a from a histogram with a known tail."""

import numpy as np
import pytest

from granboltz.analysis.tail_swpm import core_density, effective_counts, resolved_depth, swpm_tail_summary, swpm_verdict

LOCAL = {"pool_min_count": 400, "half_width": 4, "step": 2, "far_ci": 0.15, "tail_from": 0.01}


def shells_of(density, R=40.0, K=128, total=1e7, N=16):
    """Shells whose fractions follow `density` (a function of r) exactly, with the multinomial
    standard errors of `total` particles in N ensembles and the expected counts."""
    edges = np.linspace(0.0, R, K + 1)
    r = 0.5 * (edges[1:] + edges[:-1])
    frac = density(r) * 4 * np.pi / 3 * (edges[1:] ** 3 - edges[:-1] ** 3)
    frac /= frac.sum()
    counts = np.floor(frac * total).astype(np.int64)
    se = np.sqrt(frac * (1 - frac) / total)
    return {"edges": edges, "frac": frac, "se": se, "counts": counts, "N": N, "n": int(total / N)}


def test_core_density_is_f_at_zero_of_a_smooth_core():
    s = shells_of(lambda r: np.exp(-r**2 / 20) * 3.0)
    frac_density = s["frac"][0] / (4 * np.pi / 3 * s["edges"][1] ** 3)
    # the innermost shell's density is f(r ~ 0.23); the core fit extrapolates to r = 0
    assert core_density(s) == pytest.approx(frac_density, rel=5e-3)


def test_resolved_depth_is_where_the_relative_half_width_reaches_30_percent():
    f = lambda r: np.exp(-0.73 * (np.sqrt(r**2 + 9) - 3))  # noqa: E731  (smooth core, f(0) = 1, tail e^{-0.73 r})
    s = shells_of(f, total=1e8)
    depth, r = resolved_depth(s)
    rel = 3.2 * s["se"] / s["frac"]
    k = np.flatnonzero(rel < 0.3).max()
    assert r == pytest.approx(0.5 * (s["edges"][k] + s["edges"][k + 1]))
    assert depth == pytest.approx(f(r), rel=0.05)
    # an isolated far shell that passes by chance does not count (the profile must be contiguous)
    s["se"][k + 5] = 0.01 * s["frac"][k + 5]
    assert resolved_depth(s)[1] == pytest.approx(r)


def test_effective_counts_are_the_particle_counts_for_poisson_errors():
    s = shells_of(lambda r: np.exp(-0.5 * r))
    eff = effective_counts(s)["counts"]
    ok = s["counts"] > 100
    assert np.allclose(eff[ok], s["counts"][ok] / (1 - s["frac"][ok]), rtol=0.01)  # binomial: n f / (1 - f)


@pytest.mark.parametrize("example,b", [(7, 1.0), (8, 1.5)])
def test_summary_recovers_b_and_a_of_a_known_tail(example, b):
    a = {7: 0.7303, 8: 0.4869}[example]
    s = shells_of(lambda r: np.exp(-a * r**b), R=40.0 if example == 7 else 16.0, total=1e12)
    summary, _ = swpm_tail_summary(s, example, LOCAL, constant=s)
    assert summary["b_swpm"] == pytest.approx(b, abs=0.02) and summary["a_swpm"] == pytest.approx(a, rel=0.05)
    assert summary["depth_swpm"] == summary["depth_constant"] < 1e-8
    ok, text = swpm_verdict(summary)
    assert text.startswith("agrees with the goal" if ok else "differs from the goal")


def test_verdict_names_why_there_is_no_b():
    # No fitted b: either the resolved profile never reached the tail, or it did and the joint fit
    # of a, b and chi did not converge; the verdict must say which.
    base = {"theory_b": 1.0, "a_theory": 0.73, "b_swpm": float("nan"), "b_swpm_ci": float("nan"),
            "a_swpm": float("nan"), "depth_swpm": 9e-8, "depth_constant": 2.6e-8}
    ok, text = swpm_verdict({**base, "fit_r_lo": 11.7, "fit_r_hi": 28.4})
    assert not ok and "does not converge" in text and "11.7" in text
    ok, text = swpm_verdict({**base, "depth_swpm": 0.05, "fit_r_lo": 12.0, "fit_r_hi": 3.0})
    assert not ok and "no tail to fit" in text
