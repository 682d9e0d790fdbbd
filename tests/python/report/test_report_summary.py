"""The summary of the report lists each item once: the figure and the data table one rule makes
share a row, with the strongest outcome of the two; every part keeps its own section."""

from granboltz.report import Verdict, build_document, render_md
from granboltz.report.summary import summary_rows

EMPTY = {"tables": {}, "published": {}, "summaries": {}, "bench": {}, "runs": {}}
MACHINE = {k: "x" for k in ("uname", "cpu", "cores", "python", "snakemake", "numpy", "scipy", "h5py", "matplotlib")}


def _item(name, rule, kind, paper="Beyond the papers"):
    return {"paper": paper, "item": name, "rule": rule, "kind": kind, "output": f"{name}.{kind}", "what": name}


def test_a_figure_and_its_table_are_one_row_naming_both():
    parts = [(_item("Haff's law", "beyond_haff", "figure"), "agrees within the statistics (max 1.5σ)"),
             (_item("Haff's law (table)", "beyond_haff", "table"), "agrees within the statistics (max 1.5σ)"),
             (_item("HCS tail", "beyond_tail", "figure"), "not yet asymptotic")]
    rows = summary_rows("Beyond the papers", parts)
    assert len(rows) == 2
    assert rows[0] == ["Beyond the papers", "[Haff's law](#beyond-the-papers-haffs-law) (figure and "
                       "[table](#beyond-the-papers-haffs-law-table))",
                       "✓ agrees within the statistics (max 1.5σ)", "`beyond_haff`"]
    assert rows[1] == ["Beyond the papers", "[HCS tail](#beyond-the-papers-hcs-tail)", "· not yet asymptotic",
                       "`beyond_tail`"]


def test_an_item_takes_the_strongest_outcome_of_its_parts():
    """✗ in the table of an item whose figure agrees: the item's row is ✗ (counted once), and both
    texts are kept, each named by its part."""
    parts = [(_item("Fig. 3", "tv06_fig3", "figure", "TV06"), "agrees: 11/11 points within the CI"),
             (_item("Fig. 3 data", "tv06_fig3", "table", "TV06"), Verdict("differs", "2 point(s) outside the CI"))]
    [row] = summary_rows("TV06", parts)
    assert row[2] == "✗ figure: agrees: 11/11 points within the CI; table: 2 point(s) outside the CI"
    assert row[1] == "[Fig. 3](#tv06-fig-3) (figure and [table](#tv06-fig-3-data))"


def test_the_document_has_one_summary_row_per_item_and_every_section():
    items = [{**_item(name, rule, kind), "runs": [], "benchmarks": [f"benchmarks/{rule}.tsv"], "compare": None, "published": None,
              "summary": None, "extra": [], "output": f"figures/{rule}.png"}
             for name, rule, kind in (("Haff's law", "beyond_haff", "figure"),
                                      ("Viscoelastic free cooling", "beyond_viscoelastic", "figure"))]
    doc = build_document(items, EMPTY, "", MACHINE, "quick")
    summary = next(b for b in doc if b[0] == "table")
    assert len(summary[2]) == 2
    # a figure registered twice by one rule would be one row; each registration keeps its section
    items.append({**items[0], "item": "Haff's law (again)"})
    doc = build_document(items, EMPTY, "", MACHINE, "quick")
    summary = next(b for b in doc if b[0] == "table")
    text = render_md(doc)
    assert len(summary[2]) == 2 and "### Beyond the papers Haff's law (again)" in text
