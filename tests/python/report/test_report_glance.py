"""What a reader sees of the report at a glance: text columns left-aligned and numbers right-
aligned (HTML and Markdown), a verdict mark and colour for agrees / differs / published number
questioned, and only files that exist named as the report's source."""

import re

from granboltz.report import build_document, marked, numeric_columns, render_html, render_md, verdict_kind
from conftest import ROOT

EMPTY = {"tables": {}, "published": {}, "summaries": {}, "bench": {}, "runs": {}}
MACHINE = {k: "x" for k in ("uname", "cpu", "cores", "python", "snakemake", "numpy", "scipy", "h5py", "matplotlib")}

# short verdicts as the comparisons and figure scripts write them
SHORTS = {
    "agrees within the statistics (max 1.2σ)": "agrees",
    "agrees: 11/11 points within the CI of eq. (18) (max 2.1σ)": "agrees",
    "repeats agree with the exact expectation (max 1.1 s.e.); real spread 1.80 × nominal σ": "agrees",
    "differs in a row (max 4.1σ)": "differs",
    "differs: b = 1.25, 1.59 on [4.25, 4.6] against theory 1, 1.5 (max deviation 0.254)": "differs",
    "**repeats differ from the exact expectation** (4.0 s.e.); real spread 1.80 × nominal σ": "differs",
    "2 point(s) outside the CI: 9/11 points within the CI of eq. (18) (max 5.0σ)": "differs",
    "check: R = 1 within CI at α = 1 (0/1); T_B > T_trans > T_rot at 3/3 points with α < 1": "differs",
    "agrees within the statistics (max 2.0σ); published n = 64 is +3.6σ from the exact expectation": "questioned",
    "errors agree within the statistics (max 1.1σ); Conf_end differs by a constant factor ≈ 8.5, same CF":
        "questioned",
    "generated (no published numbers to compare)": "approximation",
    "from Crit(0) ≤ 0.031 to 0.046, 0.065 (increasing in n)": "approximation",
}


def test_every_kind_of_short_verdict_gets_its_mark():
    for short, kind in SHORTS.items():
        assert verdict_kind(short) == kind, short
    assert marked("differs in a row (max 4.1σ)") == "✗ differs in a row (max 4.1σ)"
    assert {marked(s)[0] for s in SHORTS} == {"✓", "✗", "⚠", "·"}


def test_numbers_are_right_aligned_and_text_left_aligned():
    header = ["item", "n", "E_max ours ± ci", "verdict", "paper − expected", "shells", "note"]
    rows = [["Table 1", 64, "0.0850 ± 0.0012", "agrees (1.2σ)", "+3.3σ", "12", "–"],
            ["Table 2", 256, "2.1e-3 ± 4e-4", "**differs** (4.0σ)", "-0.2σ", "", "statistical error dominates"]]
    assert numeric_columns(rows, len(header)) == [False, True, True, False, True, True, False]
    page = render_html([("table", header, rows)], lambda p: b"", "t")
    assert '<th>item</th><th class="num">n</th><th class="num">E_max ours ± ci</th><th>verdict</th>' in page
    assert "<td>Table 1</td>" in page and '<td class="num">64</td>' in page and "<td>agrees (1.2σ)</td>" in page
    assert re.search(r"th,td\{[^}]*text-align:left", page) and re.search(r"td\.num\{text-align:right\}", page)
    md = render_md([("table", header, rows)])
    assert "\n|---|---:|---:|---|---:|---:|---|\n" in md


def test_a_marked_verdict_cell_carries_its_colour_class():
    rows = [["GRW05", "[Table 1](#grw05-table-1)", marked(s), "`rule`"] for s in SHORTS]
    page = render_html([("table", ["paper", "item", "verdict", "rule"], rows)], lambda p: b"", "t")
    for kind in ("agrees", "differs", "questioned", "approximation"):
        assert re.search(rf'<td class="{kind}"><span class="mark">.</span> ', page), kind
    for kind, colour in (("agrees", "#1b7a2f"), ("differs", "#c62828"), ("questioned", "#b26a00"),
                         ("approximation", "#1f4e8c")):
        assert f".{kind} .mark{{color:{colour}}}" in page
    md = render_md([("table", ["paper", "item", "verdict", "rule"], rows)])
    assert "| ✓ agrees within the statistics (max 1.2σ) |" in md and "| ⚠ errors agree" in md


def test_the_summary_explains_the_marks():
    text = render_md(build_document([], EMPTY, "", MACHINE, "quick"))
    assert "Verdicts: ✓ agrees with the exact result" in text
    assert "⚠ ours agrees with the exact result, a published number does not" in text
    assert "· compared with an approximation" in text and "✗ disagrees with an exact result" in text


def test_the_report_names_only_files_that_exist():
    text = render_md(build_document([], EMPTY, "", MACHINE, "quick"))
    named = set(re.findall(r"`((?:workflow|src|config|docs)/[^`*…]+)`", text))
    assert {"workflow/scripts/report.py", "workflow/rules/report.smk", "src/python/granboltz/report/"} <= named
    missing = [p for p in named if not (ROOT / p).exists()]
    assert not missing, missing
