"""GRW05 §5.3 tails: the texts and verdicts of the figure summaries of Figs. 5-7 (eq. 38), the
local exponents, the weighted-particle (SWPM) tails and their importance check, from the numbers
the workflow scripts compute.  Pure functions: numbers in, (verdict, text, short) out; the scripts
plot and write.
"""

import numpy as np

from ..analysis.tail_local import local_verdict
from ..analysis.tail_swpm import swpm_kind, swpm_verdict
from ..analysis.tails import window_text

# The weighted-particle goal's tolerances on b and on a (relative), as swpm_verdict's defaults.
B_TOL, A_REL = 0.03, 0.05
# A fit's b is resolved when its half-width is at most this (as swpm_kind's resolved_ci).
RESOLVED_CI = 0.1


def tail_plot_verdict(example, lam, fit, fit_window, x_last, k_last):
    """(text, short) of GRW05 Figs. 5-7: the least-squares slope b of eq. (38) (analysis.tails.fit_tail
    on fit_window) against the theory 1 + lambda/2; (x_last, k_last) the last point drawn."""
    window = window_text(fit_window)
    text = (f"Example {example} (λ = {lam:g}): y_k nearly linear up to x = {x_last:.2f} (k = {k_last}); "
            f"least-squares slope b = {fit['b']:.3f} ± {fit['b_stderr']:.3f} on x ∈ {window}"
            f" ({fit['points']} shells), theory {1 + lam / 2:g}")
    short = f"b = {fit['b']:.3f} ± {fit['b_stderr']:.3f} on {window} (theory {1 + lam / 2:g})"
    return text, short


def tail_local_verdict(s, example, lam):
    """(text, short) of the local exponent of one example: short is analysis.tail_local.local_verdict
    of the summary s (local_tail_summary); the text adds where the data run out and the eq. (38)
    slope expected on the paper's window."""
    short = local_verdict(s)
    text = (f"Example {example} (λ = {lam:g}): {short.split(': ', 1)[1]}; data run out at r = {s['r_limit']:.3g}; "
            f"eq. (38) slope expected on the paper's window {s['b_eq38_expected_paper']:.3f}")
    return text, short


def tail_swpm_item_verdict(s, example):
    """(reached, kind, text, short) of the weighted-particle tail of one example: the goal
    (analysis.tail_swpm.swpm_verdict) and the report's outcome (swpm_kind) of its summary s."""
    ok, short = swpm_verdict(s)
    return ok, swpm_kind(s), f"Example {example}: {short}", short


def importance_label(split):
    """The name of an importance function exp(-rate r^power) (a run's split: rate, power)."""
    return f"importance exp(−{split['rate']:.3g} r^{split['power']:g})"


def swpm_check_verdict(theory, check, theory_split, check_split):
    """(reached, kind, text, short) of the importance check: the SWPM summaries (swpm_tail_summary)
    of one example run with the theory's importance function (theory) and with another shape
    (check).  Reached when the two b agree within B_TOL and the two a within A_REL; whether they
    also agree within the fits' half-widths is said (those treat the shells as independent).
    Both estimate the same tail: a resolved difference (both half-widths of b at most RESOLVED_CI)
    beyond B_TOL plus the combined half-width 'differs'; estimates too wide to resolve b judge
    nothing ('approximation')."""
    t, c = theory, check
    db, da = c["b_swpm"] - t["b_swpm"], c["a_swpm"] - t["a_swpm"]
    hb, ha = np.hypot(t["b_swpm_ci"], c["b_swpm_ci"]), np.hypot(t["a_swpm_ci"], c["a_swpm_ci"])
    ok = bool(np.isfinite(db) and abs(db) <= B_TOL and abs(da) <= A_REL * t["a_swpm"])
    within = "within" if abs(db) <= hb and abs(da) <= ha else "beyond"
    text = (f"with {importance_label(check_split)}: b = {c['b_swpm']:.3f} ± {c['b_swpm_ci']:.3f}, a = "
            f"{c['a_swpm']:.3f} ± {c['a_swpm_ci']:.3f}, resolved to f/f(0) = {c['depth_swpm']:.1e}; with the theory's "
            f"{importance_label(theory_split)}: b = {t['b_swpm']:.3f} ± {t['b_swpm_ci']:.3f}, a = {t['a_swpm']:.3f} ± "
            f"{t['a_swpm_ci']:.3f}, {t['depth_swpm']:.1e}; difference b {db:+.3f}, a {da:+.3f} "
            f"({100 * da / t['a_swpm']:+.1f} %), {within} the fits' combined half-widths ± {hb:.3f}, ± {ha:.3f} (they "
            f"treat the shells as independent) and {'within' if ok else 'beyond'} the goal's tolerances "
            f"{B_TOL:g} and {100 * A_REL:g} %")
    short = (("agrees: " if ok else "differs: ") + f"b {db:+.3f}, a {100 * da / t['a_swpm']:+.1f} % between the two "
             f"importances (goal tolerances {B_TOL:g}, {100 * A_REL:g} %; {within} the fits' half-widths ± {hb:.3f}, "
             f"± {ha:.3f})")
    resolved = bool(np.isfinite(db) and max(t["b_swpm_ci"], c["b_swpm_ci"]) <= RESOLVED_CI)
    kind = "agrees" if ok else ("differs" if resolved and abs(db) > hb + B_TOL else "approximation")
    return ok, kind, text, short
