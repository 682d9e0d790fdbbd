"""The report generator (granboltz.report, report.py) and the LaTeX writer (latex_table.py):
comparisons and verdicts, Markdown and self-contained HTML, escaping."""

import json
import math
import re

import matplotlib
import numpy as np
import pytest

from granboltz.reproduction.dsmc import read_dsmc, read_histogram, read_steady
from granboltz.output.files import read_csv, write_csv
from granboltz.output.plotting import figure_summary, pyplot, save_figure
from granboltz.report import (build_document, compare_convergence, num, render_html, render_md, rounding_ci,
                              signed_z, verdict, z_score)
from granboltz.report.latex import latex_escape, latex_file, latex_table
from granboltz.reproduction.steady import (EFFORT_COLUMNS, effort_rows, REPLICA_COLUMNS, replica_rows, STEADY_COLUMNS,
                              steady_rows)
from granboltz.reproduction.tables import (convergence_rows, RW05_TABLE1_COLUMNS, rw05_table1_rows, RW05_TABLE2_COLUMNS,
                              TABLE_COLUMNS, timestep_rows)
from granboltz.analysis.tails import TAIL_COLUMNS, tail_rows, WINDOW_COLUMNS
from conftest import (ROOT, write_fake_histogram_run, write_fake_run, write_fake_scheme_run,
                      write_fake_steady_run)

matplotlib.use("Agg")


# ----------------------------------------------------------------------------- small pieces
def test_latex_escape_handles_every_special_character_once():
    assert latex_escape(r"a_b & 50% #1 {x} ~y ^z $w \q") == (
        r"a\_b \& 50\% \#1 \{x\} \textasciitilde{}y \textasciicircum{}z \$w \textbackslash{}q")


def test_latex_table_is_a_booktabs_tabular():
    text = latex_table(["n", "E_max", "kernel", "fit_window"], [["64", "0.0895", "hard_spheres", "[4.25, 4.6]"],
                                                                    ["256", "", "vhs", "[1, 2]"]])
    lines = text.splitlines()
    assert lines[0] == r"\begin{tabular}{rrll}" and lines[1] == r"\toprule" and lines[3] == r"\midrule"
    assert lines[2] == r"$n$ & $E_{\max}$ & kernel & fit\_window \\"
    assert lines[4] == r"64 & 0.0895 & hard\_spheres & [4.25, 4.6] \\" and lines[5].startswith("256 & -- &")
    assert lines[-2:] == [r"\bottomrule", r"\end{tabular}"]


def test_each_golden_latex_table_is_its_golden_csv_written_by_latex_file():
    # check-tables compares both files of each table; a CSV updated on purpose without its .tex
    # would otherwise show up only after make reproduce.
    golden = ROOT / "tests" / "golden" / "quick_tables"
    pairs = [(p, p.with_suffix(".tex")) for p in sorted(golden.glob("*.csv")) if p.with_suffix(".tex").exists()]
    assert pairs
    for path, tex in pairs:
        expected = latex_file(path, source=f"results/tables/{path.name}")
        assert tex.read_text() == expected, f"{tex.name} is not {path.name} as LaTeX"


def test_rounding_and_sigma_distances():
    assert rounding_ci("0.895e-01") == pytest.approx(3.2 * 1e-4 / math.sqrt(12))
    assert rounding_ci("2.9226") == pytest.approx(3.2 * 1e-4 / math.sqrt(12))
    assert rounding_ci("16384") == pytest.approx(3.2 / math.sqrt(12))
    assert z_score(1.0, 1.3, 0.3, 0.4) == pytest.approx(0.3 / (0.5 / 3.2))
    assert verdict(3.1).startswith("agrees") and "differs" in verdict(3.3)
    assert signed_z(1.0, 0.9, 0.32) == "+1.0σ"
    assert num(0.0895) == "0.0895" and num(3.05e-4) == "3.05e-4" and num(None) == "–"


def test_markdown_and_html_render_one_document():
    doc = [("h", 1, "Title"), ("p", "a `code` and **bold** [link](#title) <b>"), ("ul", ["one", "two|x"]),
           ("table", ["a", "b|c"], [["1", "x|y"]]), ("code", "k: v\n"), ("img", "fig.png", "alt")]
    md = render_md(doc)
    assert "# Title" in md and "| a | b\\|c |" in md and "![alt](../fig.png)" in md and "```\nk: v\n```" in md
    page = render_html(doc, lambda path: b"\x89PNG fake", "T")
    assert '<h1 id="title">Title</h1>' in page and "<code>code</code>" in page and "<strong>bold</strong>" in page
    assert '<a href="#title">link</a>' in page and "&lt;b&gt;" in page and "data:image/png;base64," in page


# ----------------------------------------------------------------------------- the whole report
def _write_csv(rows, columns, path):
    write_csv(rows, columns, str(path))
    return str(path)


def _figure(tmp_path, name):
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(2, 1.5))
    ax.plot([0, 1], [0, 1])
    png = tmp_path / f"{name}.png"
    save_figure(fig, [str(png)])
    summary = tmp_path / f"{name}.json"
    summary.write_text(json.dumps(figure_summary(f"ours for {name}", f"short {name}")))
    return str(png), str(summary)


def _bench(tmp_path, name, seconds):
    path = tmp_path / f"{name}.tsv"
    path.write_text(f"s\th:m:s\n{seconds}\t0:00:01\n")
    return str(path)


def synthetic_report_inputs(tmp_path):
    """Every kind of item, with tables computed by the granboltz package from fake runs."""
    pub = ROOT / "config" / "published"
    runs = [write_fake_run(tmp_path / f"g{n}.h5", n, eps=5.4 / n) for n in (64, 256, 1024, 4096)]
    read = [read_dsmc(p) for p in runs]
    items, tables = [], {}

    def item(paper, name, kind, output, compare=None, published=None, summary=None, extra=(), run_paths=(),
             rule=None):
        bench = [_bench(tmp_path, f"b{len(items)}", 1.5)]
        items.append({"paper": paper, "item": name, "rule": rule or f"rule_{len(items)}", "kind": kind, "output": output,
                      "what": f"what {name}", "runs": [str(p) for p in run_paths], "benchmarks": bench,
                      "compare": compare, "published": str(pub / f"{published}.csv") if published else None,
                      "summary": summary, "extra": list(extra)})

    t = _write_csv(convergence_rows(read), TABLE_COLUMNS, tmp_path / "grw05_table1.csv")
    item("GRW05", "Table 1", "table", t, "convergence", "grw05_table1", run_paths=runs)
    rw = [read_dsmc(write_fake_run(tmp_path / f"r{n}.h5", n, eps=5.4 / n)) for n in (16, 64, 256)]
    item("RW05", "Table 1", "table", _write_csv(rw05_table1_rows(rw), RW05_TABLE1_COLUMNS,
                                                   tmp_path / "rw05_table1.csv"), "rw05_table1", "rw05_table1")
    eu = [read_dsmc(write_fake_scheme_run(tmp_path / f"e{K}.h5", 4096, "euler", K)) for K in (4, 8, 16, 32)]
    st = [read_dsmc(write_fake_scheme_run(tmp_path / f"s{K}.h5", 4096, "strang", K)) for K in (4, 8, 16, 32)]
    item("RW05", "Table 2", "table", _write_csv(timestep_rows(eu, st, 8.0), RW05_TABLE2_COLUMNS,
                                                   tmp_path / "rw05_table2.csv"), "rw05_table2", "rw05_table2")
    nosplit = read_steady(write_fake_steady_run(tmp_path / "n.h5", 65536, T_inf=2.668))
    reps = [read_steady(write_fake_steady_run(tmp_path / f"rep{i}.h5", 65536, T_inf=2.668 + 0.002 * i))
            for i in range(3)]
    replica = _write_csv(replica_rows([reps], 8.0), REPLICA_COLUMNS, tmp_path / "rw05_steady_replicas.csv")
    for name, layout, steadies in (
            ("table3_euler", "steps", [read_steady(write_fake_steady_run(tmp_path / f"se{K}.h5", 65536, "euler", K,
                                                                            T_inf=2.92)) for K in (32, 256)]),
            ("table5_nosplit", "single", [nosplit])):
        t = _write_csv(steady_rows(steadies, nosplit, 8.0), STEADY_COLUMNS[layout], tmp_path / f"rw05_{name}.csv")
        item("RW05", f"Table {name[5]}", "table", t, "steady", f"rw05_{name}", extra=[replica])
    item("RW05", "Steady repeats", "table", replica, "replicas")
    effort = effort_rows([nosplit, read_steady(tmp_path / "se32.h5")], 8.0, 8.0)
    item("RW05", "Effort", "table", _write_csv(effort, EFFORT_COLUMNS, tmp_path / "rw05_effort.csv"), "effort")
    hists = {ex: read_histogram(write_fake_histogram_run(tmp_path / f"h{ex}.h5", lam=lam, b=1 + lam / 2))
             for ex, lam in ((7, 0.0), (8, 1.0), (9, 0.5))}
    tails = {"k0": 1, "min_count": 1, "histogram": "density", "fit_window": [2.0, 3.0], "windows": [[1.0, 2.0]]}
    rows, wrows = tail_rows(hists, tails)
    windows = _write_csv(wrows, WINDOW_COLUMNS, tmp_path / "grw05_tail_windows.csv")
    item("GRW05", "Tail exponents", "table", _write_csv(rows, TAIL_COLUMNS, tmp_path / "grw05_tail_exponents.csv"),
         "tails", "grw05_tail_exponents", extra=[windows])
    png, summary = _figure(tmp_path, "grw05_fig1")
    item("GRW05", "Fig. 1", "figure", png, summary=summary, run_paths=runs[:2])
    png, summary = _figure(tmp_path, "tv06_fig1")
    item("TV06", "Fig. 1", "figure", png, summary=summary)
    # a figure and its data table from one rule: one item of the summary, two sections
    item("TV06", "Fig. 1 data", "table", _write_csv([{"a": 0.5, "phi": 1.2}], ["a", "phi"], tmp_path / "tv06_fig1.csv"),
         rule=items[-1]["rule"])
    return items


def summary_table(text):
    """The rows of the summary table of a Markdown report, split into cells."""
    block = text.split("\n## Summary\n", 1)[1].split("\n## ", 1)[0]
    lines = [line for line in block.splitlines() if line.startswith("| ")]
    return [re.split(r"(?<!\\)\|", line.strip("| "))[:4] for line in lines[1:]]  # [0]: the header


def test_report_contains_every_item_and_the_html_is_self_contained(run_script, tmp_path):
    items = synthetic_report_inputs(tmp_path)

    def uniq(xs):
        return list(dict.fromkeys(x for x in xs if x))

    inputs = {
        "tables": uniq([i["output"] for i in items if i["kind"] == "table"] + [e for i in items for e in i["extra"]]),
        "tex": [],
        "figures": uniq(i["output"] for i in items if i["kind"] == "figure"),
        "summaries": uniq(i["summary"] for i in items),
        "published": uniq(i["published"] for i in items),
        "benchmarks": uniq(b for i in items for b in i["benchmarks"]),
        "runs": uniq(r for i in items for r in i["runs"]),
    }

    class Input(dict):  # snakemake.input: iterable over all files, with named lists
        def __iter__(self):
            return iter([p for v in self.values() for p in v])

        def __getattr__(self, name):
            return self[name]

    md, html = tmp_path / "paper" / "reproduction.md", tmp_path / "paper" / "reproduction.html"
    machine = {k: "x" for k in ("uname", "cpu", "cores", "python", "snakemake", "numpy", "scipy", "h5py",
                                "matplotlib")}
    import runpy
    import sys
    import types

    figures, tables = tmp_path / "paper" / "figures", tmp_path / "paper" / "tables"
    smk = types.SimpleNamespace(input=Input(inputs),
                                output=types.SimpleNamespace(md=str(md), html=str(html), figures=str(figures),
                                                             tables=str(tables),
                                                             captions=str(tmp_path / "paper" / "captions")),
                                params=types.SimpleNamespace(manifest=items, profile="quick", config="seed: 1\n",
                                                             machine=machine),
                                log=[str(tmp_path / "report.log")])
    saved = sys.stderr
    try:
        runpy.run_path(str(ROOT / "workflow" / "scripts" / "report.py"), init_globals={"snakemake": smk})
    finally:
        sys.stderr.close()
        sys.stderr = saved
    text, page = md.read_text(), html.read_text()
    assert text.startswith("# Reproduction") and "**Profile: quick**" in text
    for it in items:
        heading = f"### {it['paper']} {it['item']}"
        assert heading in text, heading
        assert f"`{it['rule']}`" in text
        assert re.sub(r"^### ", "", heading) in page
    assert "## TV06" in text and "not in the workflow yet" not in text  # TV06 items registered here
    # the summary lists each item once: a figure and its table (one rule) share a row naming both
    rows = summary_table(text)
    assert len(rows) == len({(it["paper"], it["rule"]) for it in items}) == len(items) - 1
    assert sorted(r[3].strip() for r in rows) == sorted({f"`{it['rule']}`" for it in items})
    tv06 = [r for r in rows if r[0].strip() == "TV06"]
    assert len(tv06) == 1 and "(#tv06-fig-1)" in tv06[0][1] and "[table](#tv06-fig-1-data)" in tv06[0][1]
    # and the Snakemake report's captions: one per item (rule), each from the item's descriptions
    captions = md.parent / "captions"
    assert sorted(p.name for p in captions.iterdir()) == sorted({f"{it['rule']}.rst" for it in items})
    for it in items:
        caption = (captions / f"{it['rule']}.rst").read_text()
        assert f"— {it['what']}." in caption and f"Made by rule ``{it['rule']}``." in caption
    assert "agrees" in text and "granboltz 0.1.0 (commit `abc123`)" in text
    assert text.count("![") == 2 and page.count("data:image/png;base64,") == 2
    # the report directory stands alone: every image it links to is copied beside it
    for link in re.findall(r"!\[[^]]*\]\(([^)]+)\)", text):
        assert (md.parent / link).is_file(), link
    # self-contained: no link, script, stylesheet or image from anywhere else
    assert not re.search(r"(src|href)\s*=\s*\"(?!data:|#)", page)
    assert "http://" not in page and "https://" not in page and "<script" not in page and "<link" not in page


def test_report_refuses_an_item_whose_files_are_not_inputs(tmp_path):
    items = [{"paper": "GRW05", "item": "Table 1", "rule": "r", "kind": "table", "output": "missing.csv",
              "what": "", "runs": [], "benchmarks": [], "compare": None, "published": None, "summary": None,
              "extra": []}]
    import runpy
    import sys
    import types

    smk = types.SimpleNamespace(input=[], output=types.SimpleNamespace(md=str(tmp_path / "a.md"),
                                                                       html=str(tmp_path / "a.html")),
                                params=types.SimpleNamespace(manifest=items, profile="quick", config="", machine={}),
                                log=[str(tmp_path / "log")])
    saved = sys.stderr
    with pytest.raises(ValueError, match="not an input"):
        try:
            runpy.run_path(str(ROOT / "workflow" / "scripts" / "report.py"), init_globals={"snakemake": smk})
        finally:
            sys.stderr.close()
            sys.stderr = saved
    assert not (tmp_path / "a.md").exists()


def test_tv06_section_is_a_placeholder_without_items():
    doc = build_document([], {"tables": {}, "published": {}, "summaries": {}, "bench": {}, "runs": {}}, "",
                            {k: "x" for k in ("uname", "cpu", "cores", "python", "snakemake", "numpy", "scipy",
                                              "h5py", "matplotlib")}, "paper")
    text = render_md(doc)
    assert "**Profile: paper**" in text and "TV06 is not in the workflow yet" in text
    assert "report_item(\"TV06\"" in text


def test_convergence_comparison_flags_a_published_value_far_from_the_exact_bias(tmp_path):
    runs = [read_dsmc(write_fake_run(tmp_path / f"{n}.h5", n, eps=5.385 / n)) for n in (64, 256)]
    write_csv(convergence_rows(runs), TABLE_COLUMNS, str(tmp_path / "t.csv"))
    ours = read_csv(str(tmp_path / "t.csv"))
    published = [{"n": "64", "E_max": "0.150e+00", "CF": "", "V_inf": "0.1e-01"},
                 {"n": "256", "E_max": "0.210e-01", "CF": "7.1", "V_inf": "0.1e-01"}]
    blocks, short = compare_convergence("grw05_table1", ours, published)
    # ours agree with the exact bias, the published n = 64 does not: questioned, not a failure of ours
    assert short.kind == "questioned" and short.startswith("agrees with the exact expectation")
    assert "published n = 64 is" in short and "n = 256 is" not in short
    table = blocks[0][2]
    assert "**differs**" in table[0][9] and table[1][9].startswith("agrees")


def _csv_rows(rows, columns, path):
    write_csv(rows, columns, str(path), digits=6)
    return read_csv(str(path))


def test_the_steady_tables_say_how_much_wider_the_honest_conf_is(tmp_path):
    from granboltz.report.steady import compare_steady

    nosplit = read_steady(write_fake_steady_run(tmp_path / "n.h5", 65536, T_inf=2.668, ci=0.004,
                                                batch=(0.010, 0.0025)))
    euler = [read_steady(write_fake_steady_run(tmp_path / f"e{K}.h5", 65536, "euler", K, T_inf=2.92, ci=0.004,
                                               batch=(0.004 * r, 0.001 * r, tau)))
             for K, r, tau in ((32, 2.0, 0.5), (256, 3.0, 2.0))]
    ours = _csv_rows(steady_rows(euler, nosplit, 8.0), STEADY_COLUMNS["steps"], tmp_path / "t3.csv")
    published = [{"K": "32", "T_inf": "2.924", "Error": "0.257", "CF_Error": "", "Conf": "0.005", "CPU": "1.0"}]
    blocks, _ = compare_steady("rw05_table3_euler", ours, published)
    header, rows = blocks[0][1], blocks[0][2]
    assert header[header.index("T∞ ours ± Conf") + 1] == "Conf batch" and rows[1][3] == "0.012"
    text = " ".join(blocks[1][1])
    assert "treats the M observations of one run as independent" in text
    assert "wider by a factor of 2.50 on average (2.00–3.00 over the rows)." in text  # from the table, not typed
    assert "√(2τ_int), 1.50 on average (1.00–2.00 over the rows), is the ratio of the two standard errors" in text
    table5 = [{"T_inf": "2.6665", "Error": "0.0002", "Conf": "0.004", "CPU": "1"}]
    single = _csv_rows(steady_rows([nosplit], nosplit, 8.0), STEADY_COLUMNS["single"], tmp_path / "t5.csv")
    text = " ".join(compare_steady("rw05_table5_nosplit", single, table5)[0][1][1])
    assert "wider by a factor of 2.50." in text and "√(2τ_int)" not in text  # a file without tau_int
    # a table of files without the batch interval says nothing of it
    plain = [read_steady(write_fake_steady_run(tmp_path / "p.h5", 65536, T_inf=2.668))]
    ours = _csv_rows(steady_rows(plain, plain[0], 8.0), STEADY_COLUMNS["single"], tmp_path / "p.csv")
    assert "wider by" not in " ".join(compare_steady("rw05_table5_nosplit", ours, table5)[0][1][1])


def test_the_repeats_compare_the_spread_with_the_batch_sigma(tmp_path):
    from granboltz.report.steady import compare_replicas

    T = [2.667, 2.671, 2.663, 2.669]
    reps = [read_steady(write_fake_steady_run(tmp_path / f"r{i}.h5", 65536, T_inf=t, ci=3.2 * 0.002,
                                              batch=(0.013, 0.004))) for i, t in enumerate(T)]
    ours = _csv_rows(replica_rows([reps], 8.0), REPLICA_COLUMNS, tmp_path / "rep.csv")
    blocks, short = compare_replicas("rw05_steady_replicas", ours)
    sd = np.std(T, ddof=1)
    assert f"{sd / 0.002:.2f} × nominal σ, {sd / 0.004:.2f} × batch σ" in short
    assert blocks[0][2][0][blocks[0][1].index("sd / batch σ")] == f"{sd / 0.004:.2f}"
    assert f"the real spread is {sd / 0.004:.2f} (nosplit) × batch σ" in " ".join(blocks[1][1])
