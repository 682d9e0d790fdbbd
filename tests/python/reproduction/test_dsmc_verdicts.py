"""The summary texts of the GRW05/RW05 DSMC figures (granboltz.reproduction.dsmc_verdicts) on
numbers with known answers: each branch the numbers decide."""

from granboltz.reproduction import dsmc_verdicts as dv


def test_temperature_bands_count_the_times_inside():
    text, short = dv.temperature_bands_verdict({64: (40, 41), 256: (41, 41)}, (0.0, 8.0))
    assert text == ("n = 64: analytic curve inside the band at 40/41 of the t_m in [0, 8]; "
                    "n = 256: analytic curve inside the band at 41/41 of the t_m in [0, 8]")
    assert short == "analytic curve inside the band at 40/41 (n = 64), 41/41 (n = 256)"


def test_temperature_curves_order_and_convergence():
    text, short, gaps = dv.temperature_curves_verdict([(64, 1.3, 0.01), (256, 1.2, 0.01), (1024, 1.15, 0.01)], 8.0)
    assert short == "curves ordered from above in n, converging"
    assert text.startswith("T(8) = 1.3000 ± 0.0100 (n = 64), ") and text.endswith("shrinking (convergence)")
    assert gaps == [1.3 - 1.2, 1.2 - 1.15]
    text, short, _ = dv.temperature_curves_verdict([(64, 1.2, 0.01), (256, 1.3, 0.01), (1024, 1.1, 0.01)], 8.0)
    assert short == "curves not ordered in n" and text.endswith("; not monotone in n at this N")


def test_histogram_text():
    text, short = dv.histogram_verdict(1.0, 0.25, 16.0, 2.0, 0.0046, 0.0123, 7.5)
    assert text == ("T = 1.000 initially, 0.250 at t = 16; beyond r = 2 the final histogram holds 0.012 of the "
                    "particles (initial 0.0046), its last non-empty shell ends at r = 7.5")
    assert short == "T from 1 to 0.25; 0.012 of the particles beyond r = 2 (initially 0.0046)"


def test_crit_curves_by_n_and_by_scheme():
    ends = [("n = 256", 0.10, 0.01), ("n = 1024", 0.11, 0.005)]
    text, short = dv.crit_curves_verdict(ends, 8.0, False, [0.001, 0.0005])
    assert text == ("Crit(8) = 0.1000 ± 0.0100 (n = 256), 0.1100 ± 0.0050 (n = 1024); Crit(0) = 0.0010, 0.0005; "
                    "increasing in n (from below)")
    assert short == "from Crit(0) ≤ 0.001 to 0.100, 0.110 (increasing in n)"
    text, short = dv.crit_curves_verdict(ends[::-1], 8.0, False, [0.0005, 0.001])
    assert text.endswith("; order in n within the noise") and not short.endswith("(increasing in n)")
    schemes = [("no-splitting", 0.10, 0.01), ("Euler splitting", 0.13, 0.01)]
    text, short = dv.crit_curves_verdict(schemes, 8.0, True)
    assert short == "Crit(t_end) − no-splitting: Euler splitting +0.0300 (3.0 ci)"
    assert text.endswith("; differences to no-splitting: Euler splitting +0.0300 (3.0 ci)")


def _moment_rows(n, crit, sigma):
    return [{"n": n, "N": 16, "t": t, "crit": crit, "crit_ci": 0.01, "crit_exact": 0.1, "crit_sigma": sigma,
             "M4": 15.0, "M4_ci": 0.1, "M4_exact": 15.0, "M4_sigma": 0.5} for t in (1.0, 8.0)]


def test_rw05_moments_verdict_of_the_largest_n():
    full = {256: _moment_rows(256, 0.12, 6.0), 4096: _moment_rows(4096, 0.105, 1.6)}
    text, short = dv.rw05_moments_verdict(full, 1e-4)
    assert short.startswith("agrees: exact Crit(t) inside the n = 4096, N = 16 band at all 2 t")
    assert text.startswith(short + "; at t = 8: Crit = 0.10500 ± 0.01000 against exact 0.10000")
    assert text.endswith("smaller n: n = 256: max |σ| Crit 6.0, M4 0.5")
    full[4096] = _moment_rows(4096, 0.12, 6.4)  # the exact Crit outside the band of the largest n
    assert dv.rw05_moments_verdict(full, 1e-4)[1].startswith("differs: 2 of 2 point(s) outside")
