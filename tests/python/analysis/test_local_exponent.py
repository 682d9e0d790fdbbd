"""Tests of granboltz.analysis.local_exponent on synthetic ensembles drawn from f ~ r^chi exp(-a r^b) at fixed
seeds: the estimators recover b (and a, chi) within their bands, exclude a wrong b, do not see a
core offset, and the data limit is where the expected counts run out."""

import h5py
import numpy as np
import pytest
import yaml
from scipy import stats

from granboltz.analysis import local_exponent as le


def sample_radii(rng, n, a, b, chi):
    """|v| of f ~ |v|^chi exp(-a |v|^b) in 3-D: a |v|^b ~ Gamma((3 + chi)/b)."""
    return (rng.gamma((3 + chi) / b, size=n) / a) ** (1 / b)


def ensembles(draw, N, R, K, seed):
    """Per-ensemble shell data (overflow shell dropped after normalising) of N draws."""
    rng = np.random.default_rng(seed)
    edges = np.linspace(0, R, K + 1)
    counts = np.stack([np.histogram(draw(rng), bins=np.append(edges, np.inf))[0] for _ in range(N)])
    sh = le.shells_from_ensembles(edges, counts)
    for key in ("frac", "se", "counts"):
        sh[key] = sh[key][:-1]
    sh["per_ensemble"] = sh["per_ensemble"][:, :-1]
    return sh


@pytest.fixture(scope="module")
def hard_sphere_like():
    a, b, n, N = 0.5, 1.5, 250_000, 40
    return {"a": a, "b": b, "n": n, "N": N,
            "shells": ensembles(lambda rng: sample_radii(rng, n, a, b, 0.0), N, 16.0, 128, 1)}


def test_pooled_bins_hold_min_count_and_keep_the_mass(hard_sphere_like):
    sh = hard_sphere_like["shells"]
    P = le.pool_shells(sh, min_count=400)
    assert np.all(P["counts"] >= 400)
    a, b = P["slices"][0][0], P["slices"][-1][1]
    assert P["frac"].sum() == pytest.approx(sh["frac"][a:b].sum(), rel=1e-12)
    assert np.all(P["hi"][:-1] == P["lo"][1:])


def test_local_exponent_band_covers_the_true_b_and_excludes_a_wrong_one(hard_sphere_like):
    P = le.pool_shells(hard_sphere_like["shells"], min_count=400)
    L = le.local_exponent(P, half_width=4)
    assert len(L["r"]) > 40
    assert np.all(np.abs(L["b"] - 1.5) <= L["ci_b"])
    sharp = L["ci_b"] < 0.1  # where the band is narrow, b = 1.25 is excluded
    assert sharp.sum() > 10 and np.all(np.abs(L["b"][sharp] - 1.25) > L["ci_b"][sharp])
    far = le.far_estimate(L, max_ci=0.2)
    assert far["ci"] <= 0.2 and abs(far["value"] - 1.5) <= far["ci"]
    assert far["r"] == L["r"][np.flatnonzero(L["ci_b"] <= 0.2)[-1]]
    with pytest.raises(ValueError, match="no window"):
        le.far_estimate(L, max_ci=1e-4)


def test_tail_fit_recovers_a_and_b_with_delta_and_jackknife_bands(hard_sphere_like):
    P = le.pool_shells(hard_sphere_like["shells"], min_count=400)
    fixed = le.tail_fit(P, 3.0, 16.0, chi_free=False)
    jack = le.tail_fit(P, 3.0, 16.0, chi_free=False, jackknife_groups=20)
    for fit in (fixed, jack):
        assert abs(fit["b"] - 1.5) <= fit["ci_b"] and abs(fit["a"] - 0.5) <= fit["ci_a"]
        assert abs(fit["b"] - 1.25) > fit["ci_b"] and abs(fit["b"] - 1.75) > fit["ci_b"]
    assert 0.5 < jack["se_b"] / fixed["se_b"] < 2  # the two error estimates agree
    free = le.tail_fit(P, 3.0, 16.0, chi_free=True)
    assert abs(free["b"] - 1.5) <= free["ci_b"] and abs(free["chi"]) <= free["ci_chi"]
    assert abs(free["b"] - 1.25) > free["ci_b"]


def test_chi_free_sliding_fit_recovers_an_exponential_tail_with_prefactor():
    a, b, chi, n, N = 0.73, 1.0, 0.8, 200_000, 40
    sh = ensembles(lambda rng: sample_radii(rng, n, a, b, chi), N, 40.0, 128, 2)
    P = le.pool_shells(sh, min_count=400)
    S = le.sliding_tail_fit(P, half_width=10, step=2)
    ok = ~S["at_bound"] & (S["ci_b"] < 0.5)  # where the window constrains b (delta method valid)
    assert ok.sum() > 10
    assert np.all(np.abs(S["b"] - b)[ok] <= S["ci_b"][ok]) and np.all(np.abs(S["chi"] - chi)[ok] <= S["ci_chi"][ok])
    fit = le.tail_fit(P, 4.0, 40.0, chi_free=True)
    assert abs(fit["b"] - b) <= fit["ci_b"] and abs(fit["a"] - a) <= fit["ci_a"] and abs(fit["chi"] - chi) <= fit["ci_chi"]
    assert abs(fit["b"] - 1.25) > fit["ci_b"]


def test_local_exponent_ignores_a_gaussian_core():
    # 70 % Maxwellian (T = 1) + 30 % exponential tail (b = 1, a = 1): ln f(0) - ln f(r) = r + C'
    # with C' far from 0 (the eq. 38 slope is biased), yet b(r) = 1 where the tail dominates
    n, N = 200_000, 40

    def draw(rng):
        gauss = rng.random(n) < 0.7
        r = sample_radii(rng, n, 1.0, 1.0, 0.0)
        r[gauss] = np.linalg.norm(rng.normal(size=(gauss.sum(), 3)), axis=1)
        return r
    sh = ensembles(draw, N, 24.0, 96, 3)
    L = le.local_exponent(le.pool_shells(sh, min_count=400), half_width=4)
    far = L["r"] > 6  # the Gaussian is below 1e-3 of the tail there
    assert far.sum() > 8 and np.all(np.abs(L["b"][far] - 1.0) <= L["ci_b"][far])
    assert np.any(np.abs(L["b"][far] - 1.5) > L["ci_b"][far])  # and the band is informative
    assert np.any(np.abs(L["b"][L["r"] < 3] - 1.0) > L["ci_b"][L["r"] < 3])  # the core is not b = 1


def test_data_limit_is_where_the_expected_counts_fall_below_min_count(hard_sphere_like):
    d = hard_sphere_like
    sh = d["shells"]
    edges = sh["edges"]
    # expected total count per shell from the exact law of a |v|^b ~ Gamma(3/b)
    cdf = stats.gamma(3 / d["b"]).cdf(d["a"] * edges ** d["b"])
    expected = d["n"] * d["N"] * np.diff(cdf)
    mode = int(np.argmax(expected))
    first_low = edges[mode + int(np.argmax(expected[mode:] < 10))]
    got = le.data_limit(sh, min_count=10, max_rel_ci=np.inf)
    assert abs(got - first_low) <= 2 * (edges[1] - edges[0])
    assert le.data_limit(sh, min_count=0, max_rel_ci=0.1) < got  # a tighter ci limit stops earlier


def test_shells_from_h5_reads_the_histogram_layout(tmp_path):
    path = tmp_path / "run.h5"
    edges = np.linspace(0, 4, 5)
    with h5py.File(path, "w") as f:
        f.attrs["config"] = yaml.safe_dump({"dsmc": {"particles": 1000}})
        f.attrs["ensembles"] = 10
        f.attrs["confidence_lambda_p"] = 3.2
        f["histogram/edges"] = edges
        f["histogram/mean"] = np.array([[0.1, 0.2, 0.3, 0.3, 0.1], [0.4, 0.3, 0.2, 0.1, 0.0]])
        f["histogram/ci"] = 3.2 * np.array([[0.01] * 5, [0.02] * 5])
        f["histogram/counts"] = np.array([[1000, 2000, 3000, 3000, 1000], [4000, 3000, 2000, 1000, 0]], dtype=np.uint64)
    sh = le.shells_from_h5(path)
    assert np.allclose(sh["frac"], [0.4, 0.3, 0.2, 0.1]) and np.allclose(sh["se"], 0.02)
    assert list(sh["counts"]) == [4000, 3000, 2000, 1000] and sh["N"] == 10 and sh["n"] == 1000
