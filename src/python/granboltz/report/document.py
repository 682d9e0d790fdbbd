"""The whole reproduction report as a document: one function per section (title, summary, one
per paper, notes, provenance), each returning blocks, and build_document joining them. The
comparison of each table with the published numbers is chosen by the item's `compare` key
(COMPARE); the summary shows each short verdict with a mark (verdict_kind)."""

from .beyond import (BEYOND, beyond_section, compare_beyond_a2, compare_beyond_disks_a2, compare_beyond_haff,
                     compare_beyond_mixture, compare_beyond_rough, compare_beyond_tail, compare_beyond_viscoelastic)
from .convergence import compare_convergence, compare_rw05_table1, compare_rw05_table2
from .hcs_tail import compare_beyond_hcs_tail_swpm
from .numbers import VERDICT_MARKS, VERDICT_MEANING, Verdict, num
from .swpm import SWPM, swpm_section
from .summary import summary_rows
from .steady import compare_effort, compare_replicas, compare_steady
from .tails import compare_ex7_moments, compare_tails
from .transport import TRANSPORT, compare_shear_rheology, compare_transport_coefficients, transport_section
from .tv06 import compare_tv06_dsmc, compare_tv06_needle, compare_tv06_temperature


def plain_table(name, ours, published=None, **_):
    """A generated table without published numbers (e.g. TV06 figure data): shown as it is."""
    header = list(ours[0]) if ours else []
    rows = [[r[h] for h in header] for r in ours[:40]]
    more = [("p", f"({len(ours) - 40} more rows in the CSV.)")] if len(ours) > 40 else []
    return [("table", header, rows)] + more, "generated (no published numbers to compare)"

COMPARE = {"convergence": compare_convergence, "rw05_table1": compare_rw05_table1,
           "rw05_table2": compare_rw05_table2, "steady": compare_steady, "effort": compare_effort,
           "tails": compare_tails, "ex7_moments": compare_ex7_moments, "replicas": compare_replicas,
           "tv06_temperature": compare_tv06_temperature,
           "tv06_needle": compare_tv06_needle, "tv06_dsmc": compare_tv06_dsmc, None: plain_table,
           "beyond_haff": compare_beyond_haff, "beyond_a2": compare_beyond_a2, "beyond_tail": compare_beyond_tail,
           "beyond_viscoelastic": compare_beyond_viscoelastic, "beyond_disks_a2": compare_beyond_disks_a2,
           "beyond_mixture": compare_beyond_mixture, "beyond_rough": compare_beyond_rough,
           "beyond_hcs_tail_swpm": compare_beyond_hcs_tail_swpm,
           "transport_coefficients": compare_transport_coefficients, "shear_rheology": compare_shear_rheology}

# ----------------------------------------------------------------------------- the document
PAPERS = {
    "GRW05": "Gamba, Rjasanow, Wagner, Direct simulation of the uniformly heated granular Boltzmann equation, "
             "Math. Comput. Modelling 42 (2005) 683–700",
    "RW05": "Rjasanow, Wagner, Time splitting error in DSMC schemes for the inelastic Boltzmann equation, "
            "Preprint 158, Universität des Saarlandes (2005)",
    "TV06": "Talbot, Viot, Application of the Gillespie algorithm to a granular intruder particle, "
            "arXiv:cond-mat/0608158",
}
TV06_PLACEHOLDER = ("TV06 is not in the workflow yet. Its rule file `workflow/rules/tv06.smk` (included by "
                    "`workflow/Snakefile` before `report.smk`) registers each item with `report_item(\"TV06\", …)`; "
                    "the items then appear here with their figures (`figures/tv06_fig*.png`) and data tables "
                    "(`results/tables/tv06_fig*.csv`).")
NOTES = [
    "**Temperature estimator.** The error tables use φ(v) = |v|²/3 (RW05 §4.1), i.e. T + |V|²/3, as the papers did: "
    "its exact bias ((T0 + 2βt) − T(t))/n (the kicks make the bulk velocity V a random walk; collisions conserve "
    "it) is the 'expected' column and matches the published E_max; the centred temperature of GRW05 eq. (13) has "
    "the bias −T(t)/n and is shown alongside ('E_max centred').",
    "**Majorant.** Runs use the papers' update U_max := max(U_max, |v_i − V|, |v_j − V|) (GRW05 steps 2.7/2.10, "
    "RW05 eq. 21), i.e. the truncated kernel of RW05 eq. (19); `majorant_update: strict` in a profile selects "
    "the true bound 2|v − V|. For λ = 0 (all tables) it has no effect.",
    "**Tail fits.** x_k = ln(k − k0) with the shell index (see the tail-exponent section).",
    "**Typos of the published tables** read as intended: RW05 Table 1 '16 382' = 16384, Table 3 '4094' = 4096, "
    "Fig. 3 'N = 16192' = 16384.",
    "**σ-distances.** Confidence half-widths are λ_p·σ with λ_p = 3.2 (p = 0.999, GRW05 §5.1); a row 'agrees' "
    "when |ours − published| is below the combined half-width, i.e. within 3.2 combined σ. The uncertainty of a "
    "published value combines its statistical error (ours scaled to the paper's N, or its printed Conf) with its "
    "rounding (one unit of the last printed digit, uniform).",
]


def _short_path(path):
    return f"`{path}`"


def item_blocks(item, data):
    """Heading, caption and content of one registered item; returns (blocks, short verdict)."""
    title = f"{item['paper']} {item['item']}"
    blocks = [("h", 3, title)]
    made = f"Made by rule `{item['rule']}` → {_short_path(item['output'])}"
    if item["kind"] == "table":
        made += f" (LaTeX: {_short_path(item['output'][:-4] + '.tex')})"
        ours = data["tables"][item["output"]]
        published = data["published"].get(item["published"]) if item["published"] else None
        extra = [(path, data["tables"][path]) for path in item["extra"]]
        content, short = COMPARE[item["compare"]](name=item["output"].rsplit("/", 1)[-1][:-4], ours=ours,
                                                  published=published, extra=extra)
        src = f"; published numbers: {_short_path(item['published'])}" if item["published"] else ""
        blocks += [("p", f"**Paper:** {item['what']}. {made}{src}.")] + content
    else:
        summary = data["summaries"].get(item["summary"]) if item["summary"] else None
        ours = summary["ours"] if summary else "see the figure"
        short = summary.get("short", ours.split(";")[0]) if summary else ours
        if summary and summary.get("kind"):  # the outcome the figure script computed
            short = Verdict(summary["kind"], short)
        blocks += [("img", item["output"], title),
                   ("p", f"**Paper:** {item['what']}. **Ours:** {ours}. {made} (and `.pdf`).")]
    return blocks, short


def wall_times(items, bench):
    """Rows item | rule | runs | run time | step time from the benchmark seconds {path: s}."""
    rows, seen, total = [], set(), 0.0
    for it in items:
        step = bench.get(it["benchmarks"][0])
        runs = [bench[b] for b in it["benchmarks"][1:] if b in bench]
        shared = [b for b in it["benchmarks"][1:] if b in seen]
        seen.update(it["benchmarks"])
        rows.append([f"{it['paper']} {it['item']}", f"`{it['rule']}`", len(runs), num(sum(runs), 3),
                     num(step, 2), "yes" if shared else ""])
    total = sum(bench[b] for b in seen if b in bench)
    return rows, total




def title_section(profile):
    """The title, the profile and where the report comes from."""
    sized = ("the papers' particle numbers n, ensembles N and time steps" if profile == "paper" else
             "reduced particle numbers n and ensembles N (statistical errors larger than the papers'; "
             "`config/paper.yaml` has the papers' sizes)")
    return [("h", 1, "Reproduction of GRW05, RW05 and TV06 with granboltz"),
            ("p", f"**Profile: {profile}** (`config/{profile}.yaml`): {sized}."),
            ("p", "Generated by rule `report` (`workflow/rules/report.smk`, script `workflow/scripts/report.py`, "
                  "module `granboltz.report` in `src/python/granboltz/report/`). Every number below is read from a "
                  "generated file named in its caption, or from the published numbers in `config/published/`.")]


def paper_section(paper, items, data):
    """One paper's heading, reference and items; returns (blocks, summary rows)."""
    blocks, parts = [("h", 2, paper), ("p", PAPERS.get(paper, paper) + ".")], []
    mine = [it for it in items if it["paper"] == paper]
    if not mine:
        blocks.append(("p", TV06_PLACEHOLDER if paper == "TV06" else "No items registered."))
    for it in mine:
        item, short = item_blocks(it, data)
        blocks += item
        parts.append((it, short))
    return blocks, summary_rows(paper, parts)


def summary_section(summary):
    """The summary table: one row per item (a figure and its table in one) with its marked verdict,
    and the legend of the marks."""
    legend = "; ".join(f"{VERDICT_MARKS[k]} {VERDICT_MEANING[k]}" for k in VERDICT_MARKS)
    return [("h", 2, "Summary"), ("p", f"Verdicts: {legend}."),
            ("table", ["paper", "item", "verdict (computed from the numbers)", "rule"], summary)]


def notes_section():
    """The assumptions shared by several items."""
    return [("h", 2, "Notes on the reproduction"), ("ul", NOTES)]


def provenance_section(items, data, config, machine, profile):
    """Versions, machine, software, the wall time of every item and the Snakemake config."""
    versions = sorted({(a["version"], a["git_sha"]) for a in data["runs"].values()})
    rows, total = wall_times(items, data["bench"])
    return [("h", 2, "Provenance"),
            ("ul", [f"Profile: **{profile}** (`config/{profile}.yaml`); Snakemake config below.",
                    "Simulator: " + "; ".join(f"granboltz {v} (commit `{s}`)" for v, s in versions)
                    + f", from the HDF5 attributes of the {len(data['runs'])} runs.",
                    f"Machine: `{machine['uname']}`; CPU: {machine['cpu']} ({machine['cores']} cores).",
                    f"Software: Python {machine['python']}, Snakemake {machine['snakemake']}, "
                    f"NumPy {machine['numpy']}, SciPy {machine['scipy']}, h5py {machine['h5py']}, "
                    f"Matplotlib {machine['matplotlib']}."]),
            ("h", 3, "Wall time per item"),
            ("p", "From the Snakemake benchmark files (`benchmarks/…`): runs = the simulator runs behind the item "
                  "(seconds, summed; 'shared' marks runs already counted for an earlier item), step = the rule "
                  f"that makes the table or figure. Sum over all distinct jobs: {num(total, 4)} s."),
            ("table", ["item", "rule", "runs", "run time (s)", "step (s)", "shared"], rows),
            ("h", 3, "Snakemake config"), ("code", config)]


def build_document(items, data, config, machine, profile):
    """The whole report as blocks. data: tables {csv path: rows}, published {path: rows},
    summaries {json path: dict}, bench {tsv path: seconds}, runs {h5 path: attrs}."""
    body, summary = [], []
    for paper in dict.fromkeys(["GRW05", "RW05", "TV06"] + [it["paper"] for it in items if it["paper"] not in (BEYOND, SWPM, TRANSPORT)]):
        blocks, rows = paper_section(paper, items, data)
        body += blocks
        summary += rows
    if any(it["paper"] == BEYOND for it in items):  # the section Beyond the papers: after the papers
        blocks, rows = beyond_section(items, data, item_blocks)
        body += blocks
        summary += rows
    if any(it["paper"] == TRANSPORT for it in items):  # transport and rheology, after Beyond the papers
        blocks, rows = transport_section(items, data, item_blocks)
        body += blocks
        summary += rows
    if any(it["paper"] == SWPM for it in items):  # weighted particles, after the papers
        blocks, rows = swpm_section(items, data, item_blocks)
        body += blocks
        summary += rows
    return (title_section(profile) + summary_section(summary) + body + notes_section()
            + provenance_section(items, data, config, machine, profile))
