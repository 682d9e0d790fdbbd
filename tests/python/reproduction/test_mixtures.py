"""Mixtures and rough spheres (Beyond the papers): the Maxwellian theories of granboltz.reproduction.mixtures
(Garzó-Dufty temperature ratios, Martin-Piasecki) and granboltz.reproduction.rough (Huthmann-Zippelius theta)
against every number of reference/beyond.md §4 and §5 and their exact limits."""

import numpy as np
import pytest

from granboltz.reproduction import mixtures, rough

ALPHAS = (0.95, 0.9, 0.8, 0.7, 0.5)
# beyond.md §4: T1/T2 of the HCS, sigma1 = sigma2, common alpha: (m1/m2, x1) -> one value per alpha
HCS_TABLE = {(0.5, 0.5): (0.9718, 0.9438, 0.8884, 0.8340, 0.7297),
             (2, 0.5): (1.0290, 1.0596, 1.1257, 1.1990, 1.3704),
             (4, 0.5): (1.0749, 1.1566, 1.3412, 1.5544, 2.0691),
             (4, 0.2): (1.0742, 1.1593, 1.3691, 1.6420, 2.4106),
             (10, 0.5): (1.2132, 1.4638, 2.0587, 2.7474, 4.3424)}
WHITE_NOISE = {2: (1.0645, 1.1271, 1.2469, 1.3598, 1.5675), 4: (1.1624, 1.3237, 1.6425, 1.9560, 2.5665)}
# beyond.md §5, kappa = 2/5: HCS theta per alpha for beta 0, 0.5, 0.9; white noise per beta
THETA_HCS = {0.9: (0.5738, 0.8671, 1.0764), 0.7: (1.2192, 1.2262, 1.3323), 0.5: (2.0604, 1.5702, 1.5519)}
THETA_WN = (0.2222, 0.4615, 0.8444)
BETAS = (0.0, 0.5, 0.9)


@pytest.mark.parametrize("key", sorted(HCS_TABLE))
def test_hcs_ratio_matches_every_number_of_the_table(key):
    mass_ratio, x1 = key
    ours = [mixtures.temperature_ratio("gaussian", mass_ratio, a, x1) for a in ALPHAS]
    assert np.round(ours, 4).tolist() == list(HCS_TABLE[key])


@pytest.mark.parametrize("mass_ratio", sorted(WHITE_NOISE))
def test_white_noise_ratio_matches_every_number_of_the_list(mass_ratio):
    ours = [mixtures.temperature_ratio("white_noise", mass_ratio, a) for a in ALPHAS]
    assert np.round(ours, 4).tolist() == list(WHITE_NOISE[mass_ratio])


def test_ratios_are_of_the_mixture_temperature_and_solve_their_conditions():
    m, x, sig = [1.0, 2.0, 3.0], [0.2, 0.3, 0.5], [1.0, 1.2, 0.8]
    a = [[0.8, 0.7, 0.9], [0.7, 0.6, 0.8], [0.9, 0.8, 0.5]]
    g = mixtures.hcs_temperature_ratios(m, x, a, sig)
    assert np.dot(x, g) == pytest.approx(1.0, rel=1e-14)
    z = mixtures.partial_cooling_rates(g, m, x, a, sig)
    assert np.ptp(z) / z.mean() < 1e-10
    w = mixtures.white_noise_temperature_ratios(m, x, a, sig)
    q = mixtures.partial_cooling_rates(w, m, x, a, sig) * w / np.asarray(m)
    assert np.ptp(q) / q.mean() < 1e-10
    # the rates are homogeneous of degree 1/2 in the temperatures: only ratios are determined
    assert mixtures.partial_cooling_rates(4 * g, m, x, a, sig) == pytest.approx(2 * z, rel=1e-13)


def test_exact_limits():
    # equal mass, size and alpha: one gas, T1 = T2, under both thermostats
    for solve in (mixtures.hcs_temperature_ratios, mixtures.white_noise_temperature_ratios):
        assert solve([1.0, 1.0], [0.3, 0.7], 0.6) == pytest.approx([1.0, 1.0], rel=1e-12)
        assert solve([5.0, 1.0], [0.5, 0.5], 1.0) == pytest.approx([1.0, 1.0], abs=1e-9)  # equipartition
    # one species: its own temperature; alpha = 1 cools nothing
    assert mixtures.hcs_temperature_ratios([2.0], [1.0], 0.7).tolist() == [1.0]
    assert mixtures.partial_cooling_rates([2.0, 2.0], [1.0, 4.0], [0.5, 0.5], 1.0) == pytest.approx([0, 0], abs=1e-13)
    # one species: the Maxwellian cooling rate (4/3) sqrt(pi) (1 - alpha^2) n sigma^2 sqrt(T/m) of B = sigma^2 g.n
    a = 0.8
    z = mixtures.partial_cooling_rates([1.0], [1.0], [1.0], a)[0]
    assert z == pytest.approx(8 * np.sqrt(np.pi) / 3 * 0.5 * (1 + a) * 2 * (1 - 0.5 * (1 + a)), rel=1e-14)
    assert z == pytest.approx(4 * np.sqrt(np.pi) / 3 * (1 - a**2), rel=1e-14)


@pytest.mark.parametrize("alpha0, mass_ratio", [(0.9, 1.0), (0.5, 0.25), (0.3, 4.0), (0.8, 10.0)])
def test_tracer_limit_is_martin_piasecki(alpha0, mass_ratio):
    # an inelastic intruder (mass m0 = 1, alpha0 with the bath) among elastic bath particles of mass m
    x0 = 1e-10
    g = mixtures.hcs_temperature_ratios([1.0, mass_ratio], [x0, 1 - x0], [[0.5, alpha0], [alpha0, 1.0]])
    mp = mixtures.martin_piasecki(alpha0, mass_ratio)
    assert g[0] / g[1] == pytest.approx(mp, rel=1e-7)
    assert mp == (1 + alpha0) / (2 + (1 - alpha0) * mass_ratio)
    assert mixtures.martin_piasecki(1.0, 7.0) == 1.0


def test_bad_species_are_refused():
    with pytest.raises(ValueError, match="symmetric"):
        mixtures.hcs_temperature_ratios([1, 2], [0.5, 0.5], [[0.9, 0.8], [0.7, 0.9]])
    with pytest.raises(ValueError, match="sum to 1"):
        mixtures.hcs_temperature_ratios([1, 2], [0.5, 0.6], 0.9)
    with pytest.raises(ValueError, match="one entry per species"):
        mixtures.hcs_temperature_ratios([1, 2], [1.0], 0.9)


@pytest.mark.parametrize("alpha", sorted(THETA_HCS))
def test_rough_hcs_theta_matches_every_number(alpha):
    assert np.round([rough.hcs_theta(alpha, b) for b in BETAS], 4).tolist() == list(THETA_HCS[alpha])
    assert np.round(rough.theta("gaussian", alpha, np.array(BETAS)), 4).tolist() == list(THETA_HCS[alpha])


def test_rough_white_noise_theta_matches_every_number_and_ignores_alpha():
    assert np.round([rough.white_noise_theta(b) for b in BETAS], 4).tolist() == list(THETA_WN)
    assert rough.theta("white_noise", 0.3, 0.5) == rough.theta("white_noise", 0.9, 0.5)
    with pytest.raises(ValueError, match="no steady theta"):
        rough.theta("none", 0.9, 0.5)


def test_rough_theta_is_the_steady_state_of_the_two_temperature_equations():
    for alpha, beta, kappa in ((0.9, 0.0, 0.4), (0.5, 0.9, 0.4), (0.7, -0.5, 0.2), (1.0, 1.0, 2 / 3)):
        th = rough.hcs_theta(alpha, beta, kappa)
        dtr, drot = rough.temperature_rates(1.0, th, alpha, beta, kappa)
        assert drot / th == pytest.approx(dtr, rel=1e-12, abs=1e-14)  # both decay at one rate
        wn = rough.white_noise_theta(beta, kappa)
        assert rough.temperature_rates(1.0, wn, alpha, beta, kappa)[1] == pytest.approx(0, abs=1e-13)
    # alpha = beta = 1 conserves energy and ends at equipartition
    assert rough.hcs_theta(1.0, 1.0) == pytest.approx(1.0, rel=1e-14)
    dtr, drot = rough.temperature_rates(1.0, 0.3, 1.0, 1.0, 0.4)
    assert dtr + drot == pytest.approx(0, abs=1e-13)
    # beta = -1: smooth spheres, the spins untouched (no coupling, no limit)
    A, B, C = rough.coefficients(0.8, -1.0)
    assert B == 0 and C == 0 and np.isnan(rough.hcs_theta(0.8, -1.0))
    with pytest.raises(ValueError):
        rough.hcs_theta(0.8, 1.5)
