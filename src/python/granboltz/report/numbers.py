"""Numbers and verdicts of the report: formatting, σ-distances between ours and the published
values (with the rounding of a printed number as an uncertainty), verdict texts, fitted orders
and the known typos of the published tables.
"""

import math
import re

from ..reproduction.tables import fit_order
from ..theory import LAMBDA_P  # noqa: F401 (the report's modules take it from here)

# N of the published tables (from the papers' text: GRW05 §5.2, RW05 §4.1) and their typos
PUBLISHED_N = {"grw05_table1": 10000, "grw05_table2": 10000, "rw05_table1": 10000, "rw05_table2": 10000}
TYPOS = {("rw05_table3_euler", "K", "4094"): "4096"}
DASH = "–"


# ----------------------------------------------------------------------------- numbers
def fl(value):
    """A CSV cell as float (None for empty or missing)."""
    if value is None or value == "":
        return None
    return float(value)


def num(x, sig=3):
    """A number for the report: `sig` significant digits, e-notation below 1e-3; '–' for None."""
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return DASH
    x = float(x)
    if x == int(x) and abs(x) >= 1 and abs(x) < 1e7:
        return str(int(x))
    if x != 0 and (abs(x) < 1e-3 or abs(x) >= 1e6):
        mant, exp = f"{x:.{sig - 1}e}".split("e")
        return f"{mant}e{int(exp)}"
    return f"{x:.{sig}g}"


def pm(x, ci, sig=3):
    """'x ± ci': a value with its confidence half-width (two significant digits)."""
    return f"{num(x, sig)} ± {num(ci, 2)}"


def z_score(ours, published, ci_ours, ci_published):
    """|ours - published| in standard deviations; the half-widths are lambda_p sigma."""
    sigma = math.hypot(ci_ours, ci_published) / LAMBDA_P
    return abs(ours - published) / sigma if sigma > 0 else float("inf")


def rounding_ci(text):
    """The rounding of a printed number as a confidence half-width: lambda_p times the standard
    deviation unit/sqrt(12) of a uniform error over one unit of the last printed digit."""
    m = re.fullmatch(r"\s*[-+]?\d*\.?(\d*)(?:[eE]([-+]?\d+))?\s*", str(text))
    if not m:
        return 0.0
    unit = 10.0 ** (int(m.group(2) or 0) - len(m.group(1)))
    return LAMBDA_P * unit / math.sqrt(12.0)


def pci(row, key, ci_stat):
    """Uncertainty (as a half-width) of a published value: its statistical half-width ci_stat
    combined with its rounding."""
    return math.hypot(ci_stat, rounding_ci(row.get(key, "")))


def signed_z(a, b, ci):
    """(a - b) in standard deviations, for the confidence half-width ci of a - b: '+3.3σ'."""
    if a is None or b is None or not ci:
        return DASH
    return f"{(a - b) / (ci / LAMBDA_P):+.1f}σ"


def paper_outliers(pairs):
    """'; the published value is +3.3σ from the exact expectation at n = 64' for |z| > lambda_p."""
    far = [(k, z) for k, z in pairs if abs(z) > LAMBDA_P]
    return "".join(f"; published {k} is {z:+.1f}σ from the exact expectation" for k, z in far)


def verdict(z):
    """'agrees' within the statistics (|diff| below the combined 99.9 % half-width), else 'differs'."""
    return f"agrees ({z:.1f}σ)" if z <= LAMBDA_P else f"**differs** ({z:.1f}σ)"


def order_fit(x, y):
    """Order p of y = C x^-p with its standard error (granboltz.tables.fit_order: scipy
    least squares on logs); nan with fewer than two points."""
    return fit_order(x, y)


def order_text(p, se):
    """A fitted order 'p ± se' ('p' alone without a standard error, '–' for nan)."""
    return DASH if math.isnan(p) else (f"{p:.2f}" if math.isnan(se) else f"{p:.2f} ± {se:.2f}")


def fix_typos(name, rows):
    """Published rows with the known typos corrected (RW05 Table 3: K = 4094 is 4096)."""
    out = []
    for row in rows:
        row = dict(row)
        for (table, col, wrong), right in TYPOS.items():
            if table == name and row.get(col) == wrong:
                row[col] = right
        out.append(row)
    return out



# ----------------------------------------------------------------------------- verdicts at a glance
# The four outcomes of a comparison, the mark shown before each short verdict of the summary
# (Markdown and HTML), and its meaning. Only a disagreement with an exact result is a failure:
# a published number far from the exact result is questioned, and an approximation's distance
# from the simulation is a measurement of the approximation.
VERDICT_MARKS = {"agrees": "✓", "questioned": "⚠", "approximation": "·", "differs": "✗"}
VERDICT_MEANING = {"agrees": "agrees with the exact result or the published numbers",
                   "questioned": "ours agrees with the exact result, a published number does not (by kσ)",
                   "approximation": "compared with an approximation (the text says which, and by how much), "
                                    "or described where nothing exact or published exists",
                   "differs": "disagrees with an exact result"}
# The order in which the outcomes of an item's parts combine into the item's: the first present.
VERDICT_ORDER = ("differs", "questioned", "agrees", "approximation")


class Verdict(str):
    """A short verdict text with its outcome (`kind`, a key of VERDICT_MARKS), computed by the
    comparison that wrote it; a plain str everywhere else."""

    def __new__(cls, kind, text):
        if kind not in VERDICT_MARKS:
            raise ValueError(f"verdict kind {kind!r}: one of {', '.join(VERDICT_MARKS)}")
        obj = super().__new__(cls, text)
        obj.kind = kind
        return obj

    def __add__(self, more):
        return Verdict(self.kind, str(self) + more)


def combined_kind(kinds):
    """The outcome of an item from those of its parts: differs over questioned over agrees over
    approximation (an exact failure anywhere decides; approximations alone never do)."""
    kinds = set(kinds)
    return next((k for k in VERDICT_ORDER if k in kinds), "approximation")


def exact_verdict(ours, published=(), against_published=None, reference="the exact expectation", rows="rows"):
    """The verdict of a table with an exact reference: `ours` [(label, z)] the signed σ-distances
    of our values from it, `published` [(label, z)] those of the published values, and
    `against_published` the largest σ-distance of ours from the published values (or None).
    differs where one of ours is more than λ_p from the reference; else questioned where a
    published value is; else agrees."""
    far = [(k, z) for k, z in ours if abs(z) > LAMBDA_P]
    off = [(k, z) for k, z in published if abs(z) > LAMBDA_P]
    vs = "" if against_published is None else f"; ours vs published max {against_published:.1f}σ"
    if far:
        return Verdict("differs", f"differs from {reference}: " + ", ".join(f"{k} {z:+.1f}σ" for k, z in far) + vs)
    worst = max((abs(z) for _, z in ours), default=0.0)
    head = f"agrees with {reference} (max {worst:.1f}σ over {len(ours)} {rows})"
    if off:
        return Verdict("questioned", head + "; published " + ", ".join(f"{k} is {z:+.1f}σ from it" for k, z in off)
                       + vs)
    return Verdict("agrees", head + vs)


def verdict_kind(short):
    """The outcome of a short verdict: its `kind` when a comparison computed it (Verdict); else
    read from the words a figure summary or an older comparison writes: 'differs' (a row or point
    differs from an exact result), 'questioned' (ours agree, a published number lies far from the
    exact expectation or differs by a constant factor), 'agrees', or 'approximation' (compared
    with an approximation, or no comparison made)."""
    if getattr(short, "kind", None):
        return short.kind
    text = short.replace("**", "").strip().lower()
    if (text.startswith(("differs", "an error differs", "repeats differ", "check"))
            or "point(s) outside" in text or "point(s) differ" in text):
        return "differs"
    if ("published" in text and "from the exact expectation" in text) or "conf_end differs" in text:
        return "questioned"
    if text.startswith(("agrees", "errors agree", "repeats agree")):
        return "agrees"
    return "approximation"


def marked(short):
    """A short verdict with its mark in front: '✓ agrees within the statistics (max 1.2σ)'."""
    return f"{VERDICT_MARKS[verdict_kind(short)]} {short}"
