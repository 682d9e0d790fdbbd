"""The verdicts of the GRW05 tail figures (granboltz.reproduction.grw05_tails) on summaries with
known answers: each passes where the numbers agree and fails where they do not."""

import math

from granboltz.reproduction import grw05_tails as gt


def test_tail_plot_text_gives_the_fit_and_the_theory():
    fit = {"b": 1.4741, "b_stderr": 0.0123, "points": 12}
    text, short = gt.tail_plot_verdict(8, 1.0, fit, [4.25, 4.6], 4.71, 110)
    assert text == ("Example 8 (λ = 1): y_k nearly linear up to x = 4.71 (k = 110); least-squares slope "
                    "b = 1.474 ± 0.012 on x ∈ [4.25, 4.6] (12 shells), theory 1.5")
    assert short == "b = 1.474 ± 0.012 on [4.25, 4.6] (theory 1.5)"


def _local(b, ci):
    return {"b_local_far": b, "b_local_far_ci": ci, "theory_b": 1.0, "b_local_expected": 1.2, "r_far": 11.1,
            "r_far_thermal": 2.9, "f_ratio_far": 0.013, "a_fit": 0.777, "a_fit_ci": 0.018, "a_theory": 0.73,
            "b_eq38_expected": 1.326, "offset": -0.49, "chi_fit": 1.58, "r_limit": 12.3,
            "b_eq38_expected_paper": 1.25}


def test_tail_local_text_follows_the_local_verdict():
    text, short = gt.tail_local_verdict(_local(1.05, 0.1), 7, 0.0)
    assert short.startswith("agrees: consistent with b = 1 where the data reach (inside the band)")
    assert text.startswith("Example 7 (λ = 0): consistent with b = 1 where the data reach (inside the band)")
    assert text.endswith("; data run out at r = 12.3; eq. (38) slope expected on the paper's window 1.250")
    text, short = gt.tail_local_verdict(_local(1.6, 0.1), 7, 0.0)  # neither b = 1 nor 1.2 in the band
    assert short.startswith("differs") and text.startswith("Example 7 (λ = 0): not consistent with b = 1")


def _swpm(b, b_ci, a, a_ci, depth=1e-40):
    return {"b_swpm": b, "b_swpm_ci": b_ci, "a_swpm": a, "a_swpm_ci": a_ci, "theory_b": 1.0, "a_theory": 0.73,
            "depth_swpm": depth, "depth_constant": 1e-6, "fit_r_lo": 8.0, "fit_r_hi": 40.0}


def test_tail_swpm_item_verdict_reaches_the_goal_or_not():
    ok, kind, text, short = gt.tail_swpm_item_verdict(_swpm(1.01, 0.02, 0.74, 0.01), 7)
    assert ok and kind == "agrees" and short.startswith("agrees with the goal: b = 1.010 ± 0.020")
    assert text == "Example 7: " + short
    ok, kind, text, short = gt.tail_swpm_item_verdict(_swpm(1.2, 0.02, 0.74, 0.01), 7)  # b resolved, off by 0.2
    assert not ok and kind == "differs" and short.startswith("differs from the goal")
    ok, kind, _, _ = gt.tail_swpm_item_verdict(_swpm(1.2, 0.5, 0.74, 0.01), 7)  # too wide to judge
    assert not ok and kind == "approximation"


SPLITS = {"rate": 0.7302, "power": 1.0}, {"rate": 0.5, "power": 1.2}


def test_importance_label():
    assert gt.importance_label(SPLITS[0]) == "importance exp(−0.73 r^1)"


def test_swpm_check_verdict_within_and_beyond_the_tolerances():
    theory = _swpm(1.00, 0.02, 0.73, 0.01)
    ok, kind, text, short = gt.swpm_check_verdict(theory, _swpm(1.01, 0.02, 0.74, 0.01), *SPLITS)
    assert ok and kind == "agrees"
    assert short == ("agrees: b +0.010, a +1.4 % between the two importances (goal tolerances 0.03, 5 %; within the "
                     "fits' half-widths ± 0.028, ± 0.014)")
    assert text.startswith("with importance exp(−0.5 r^1.2): b = 1.010 ± 0.020")
    assert text.endswith("and within the goal's tolerances 0.03 and 5 %")
    ok, kind, text, short = gt.swpm_check_verdict(theory, _swpm(1.10, 0.02, 0.74, 0.01), *SPLITS)
    assert not ok and kind == "differs" and short.startswith("differs: b +0.100")  # resolved, beyond hb + 0.03
    ok, kind, _, _ = gt.swpm_check_verdict(theory, _swpm(1.10, 0.5, 0.74, 0.01), *SPLITS)
    assert not ok and kind == "approximation"  # b too wide to resolve: judges nothing
    ok, kind, _, short = gt.swpm_check_verdict(theory, _swpm(math.nan, math.nan, math.nan, math.nan), *SPLITS)
    assert not ok and kind == "approximation" and short.startswith("differs: b +nan")
