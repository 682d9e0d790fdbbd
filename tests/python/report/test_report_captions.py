"""The captions of the Snakemake report: one per item, made from the description its rule file
registers (report_item's "what"), rendered by Jinja2 and docutils as Snakemake renders them."""

import re

import pytest

from granboltz.report.captions import item_captions, rst_text
from conftest import ROOT

jinja2 = pytest.importorskip("jinja2")
core = pytest.importorskip("docutils.core")


def rendered(caption):
    """A caption as the Snakemake report shows it, as plain text (Snakemake 7: Jinja2 with the
    job's `snakemake` object, then reStructuredText to HTML)."""
    env = jinja2.Environment(trim_blocks=True, lstrip_blocks=True)
    text = env.from_string(caption).render(snakemake=None, categories={}, files=[])
    body = core.publish_parts(text, writer_name="html", settings_overrides={"report_level": 2,
                                                                            "halt_level": 2})["body"]
    return re.sub(r"\s+", " ", re.sub(r"<[^>]+>", "", body)).replace("&quot;", '"').replace("&lt;", "<") \
        .replace("&gt;", ">").replace("&amp;", "&").strip()


def _item(paper, item, rule, kind, what):
    return {"paper": paper, "item": item, "rule": rule, "kind": kind, "what": what}


ITEMS = [
    _item("GRW05", "Table 1", "grw05_table1", "table", "Example 3 (λ = 0, β = 1): E_max of T(t) falls like 1/n"),
    # markup of both languages in a description: shown as written
    _item("Beyond the papers", "Haff's law", "beyond_haff", "figure",
          "free cooling: T0 e^{−γπC(1−α²)t}; η*, κ* and `x`_ |y| [1]_ <z> {{ no }} {% no %} {# no #}"),
    _item("Beyond the papers", "Haff's law (table)", "beyond_haff", "table",
          "free cooling: T0 e^{−γπC(1−α²)t}; η*, κ* and `x`_ |y| [1]_ <z> {{ no }} {% no %} {# no #}"),
    _item("TV06", "Fig. 3", "tv06_fig3", "figure", "T/T_B of the intruder against α"),
    _item("TV06", "Fig. 3 data", "tv06_fig3", "table", "the points of Fig. 3 (no numbers printed)"),
]


def test_each_item_has_one_caption_that_is_its_description():
    captions = item_captions(ITEMS)
    assert list(captions) == ["grw05_table1", "beyond_haff", "tv06_fig3"]  # one per item, keyed by its rule
    assert rendered(captions["grw05_table1"]) == (
        "GRW05 Table 1 — Example 3 (λ = 0, β = 1): E_max of T(t) falls like 1/n. Made by rule grw05_table1.")
    # a figure and its table with one description: said once
    assert rendered(captions["beyond_haff"]) == (
        f"Beyond the papers Haff's law — {ITEMS[1]['what']}. Made by rule beyond_haff.")
    # a data table described on its own: both descriptions
    assert rendered(captions["tv06_fig3"]) == ("TV06 Fig. 3 — T/T_B of the intruder against α. Fig. 3 data — the "
                                               "points of Fig. 3 (no numbers printed). Made by rule tv06_fig3.")


def test_rst_text_escapes_inline_markup():
    assert rst_text("T_B *x* `y` |z|") == r"T\_B \*x\* \`y\` \|z\|"


def test_a_rule_with_items_in_two_sections_is_refused():
    with pytest.raises(ValueError, match="rule r makes items of two sections"):
        item_captions([_item("A", "x", "r", "figure", "a"), _item("B", "y", "r", "table", "b")])


def _rule_names(lines):
    """(line number, name of the rule being defined) for every line of a rule file; a rule made in a
    loop is named by its `name:` f-string, and tv06_outputs(name) makes the outputs of tv06_<name>."""
    rule = None
    for i, line in enumerate(lines):
        if m := re.match(r"\s*rule (\w+):", line):
            rule = m.group(1)
        elif re.match(r"\s*name:\s*$", line):
            rule = re.fullmatch(r'\s*f?"([^"]+)",?\s*', lines[i + 1]).group(1)
        elif line.startswith("def tv06_outputs(name"):
            rule = "tv06_{name}"
        yield i + 1, line, rule


def test_every_report_output_of_a_rule_has_that_rules_caption():
    """The report() outputs name item_caption(<rule>), <report_dir>/captions/<rule>.rst, the caption rule report writes for
    the item of their own rule; no caption file is shared by several items."""
    captions = 0
    for path in sorted((ROOT / "workflow" / "rules").glob("*.smk")):
        for number, line, rule in _rule_names(path.read_text().splitlines()):
            for arg in re.findall(r"caption=([^,]+\))", line):
                captions += 1
                want = f'item_caption("{rule}")' if "{" not in rule else f'item_caption(f"{rule}")'
                assert arg == want, f"{path.name}:{number}: caption={arg}, not {want}"
            assert "caption=" not in line or "item_caption(" in line, f"{path.name}:{number}: {line.strip()}"
    assert captions >= 40
    assert [p.name for p in (ROOT / "workflow" / "report").glob("*.rst")] == ["workflow.rst"]
