"""Green-Kubo integrals of the simulator's time correlations (dsmc.correlations) against the exact
eta and D of Maxwell molecules under the Gaussian thermostat (granboltz.transport)."""
import subprocess

import pytest

from conftest import ROOT

from granboltz.analysis import transport as measured
from granboltz.theory import transport

BINARY = ROOT / "build" / "granboltz"


def _run(tmp_path, alpha, d):
    geometry = "uniform"
    C = 1 / (4 * 3.141592653589793) if d == 3 else 1 / (2 * 3.141592653589793)  # nu = 1
    cfg = tmp_path / "c.yaml"
    cfg.write_text(f"""model: dsmc
seed: 5
ensembles: 30
dsmc:
  particles: 2000
  dimension: {d}
  geometry: {geometry}
  alpha: {alpha}
  thermostat: gaussian
  kernel: {{lambda: 0, C: {C!r}}}
  t_end: 40
  observe_every: 1
  steady_from: 2
  # lags to 24 mean free times: D's integrand decays at nu_D - zeta (0.24 at alpha = 0.6)
  correlations: {{velocity: {{levels: 5}}, stress: {{levels: 5}}, heat_flux: {{levels: 5}}}}
""")
    out = tmp_path / "o.h5"
    subprocess.run([str(BINARY), "run", str(cfg), "-q", "-o", str(out)], check=True)
    return out


@pytest.mark.parametrize("alpha, d", [(0.8, 3), (0.6, 3), (0.8, 2)])
def test_green_kubo_gives_the_exact_maxwell_eta_and_D(tmp_path, alpha, d):
    out = _run(tmp_path, alpha, d)
    exact = transport.maxwell_coefficients(alpha, d=d)
    zeta = transport.maxwell_rates(alpha, d)["zeta"]
    q = 1.0  # lambda = 0
    D, D_ci = measured.green_kubo(out, "velocity", (0.5 - q) * zeta)
    eta, eta_ci = measured.green_kubo_coefficient(out, "eta", T=1.0, zeta=zeta, q=q, d=d)
    D2, D2_ci = measured.green_kubo_coefficient(out, "D", T=1.0, zeta=zeta, q=q, d=d)
    assert abs(D - exact["D"]) < D_ci, (D, D_ci, exact["D"])
    assert abs(D2 - exact["D"]) < D2_ci, (D2, D2_ci, exact["D"])
    assert abs(eta - exact["eta"]) < eta_ci, (eta, eta_ci, exact["eta"])
    # Both stress signals' lag-0 values are the fourth moment T^2 (1 + a2) with the exact HCS a2
    # (the raw green_kubo of the stress is eta (1 + a2)); normal_stress has the stress's decay.
    a2 = transport.maxwell_hcs_a2(alpha, d)
    for name in ("stress", "normal_stress"):
        c = measured.read_correlation(out, name)
        assert abs(c["lag0"] - (1 + a2)) < c["lag0_ci"], (name, c["lag0"], c["lag0_ci"], 1 + a2)
    eta2, eta2_ci = measured.green_kubo(out, "normal_stress", (1 - q) * zeta, 1.0 / (1 + a2))
    assert abs(eta2 - exact["eta"]) < eta2_ci, (eta2, eta2_ci, exact["eta"])
    # kappa and mu from the heat flux's correlation with the exact source term (1 + 2 a2)
    for coefficient in ("kappa", "mu"):
        value, ci = measured.green_kubo_coefficient(out, coefficient, T=1.0, zeta=zeta, q=q, d=d, a2=a2)
        assert abs(value - exact[coefficient]) < ci, (coefficient, value, ci, exact[coefficient])
    # The interval is informative: D within 20 per cent (its weight grows at zeta/2 over the long lags); the collective stress (one channel in
    # d = 2) is less sharp.
    assert D_ci < 0.2 * exact["D"] and eta_ci < exact["eta"]


def test_a_missing_correlation_is_named(tmp_path):
    out = _run(tmp_path, 0.8, 3)
    with pytest.raises(KeyError, match="volume.*has heat_flux, normal_stress, stress, velocity"):
        measured.read_correlation(out, "volume")


def test_the_integral_stops_after_six_decay_times_of_its_integrand():
    import numpy as np

    t = np.arange(0, 60, 0.05)
    for rate, w in ((0.5, 0.0), (0.4, -0.1)):  # a growing weight: the integrand decays at rate + w
        cut = measured.integration_cutoff(t, np.exp(-rate * t), w)
        assert cut == pytest.approx(6 / (rate + w), rel=0.01)
    assert measured.integration_cutoff(t[:20], np.exp(-0.01 * t[:20])) is None  # the lags end first
    with pytest.raises(ValueError, match="coefficient = 'viscosity'; known: eta, D, kappa, mu"):
        measured.green_kubo_coefficient("unused.h5", "viscosity", T=1, zeta=0, q=1)
