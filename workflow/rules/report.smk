"""The report: LaTeX versions of the tables and <report_dir>/reproduction.{md,html}.

The report directory holds copies of the figures and tables it shows, so that it stands alone:
the paper profile writes it to paper/ (committed: the published artifact), the quick profile to
results/report/ (so that a quick run never overwrites the published report).

Every table and figure registered with report_item() (common.smk) by the paper rule files is an
input of rule report, with the runs and benchmark files behind it and the published numbers.
TV06 joins by registering its items in rules/tv06.smk, included before this file.
"""

import importlib
import importlib.metadata
import platform

import yaml


def machine_info():
    """Machine and software of this workflow run (for the report's provenance section)."""
    cpu = "unknown"
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next((line.split(":", 1)[1].strip() for line in f if line.startswith("model name")), cpu)
    except OSError:
        pass
    versions = {}
    for pkg in ("numpy", "scipy", "h5py", "matplotlib", "snakemake"):
        try:
            versions[pkg] = importlib.metadata.version(pkg)
        except importlib.metadata.PackageNotFoundError:  # Debian's h5py has no metadata
            versions[pkg] = getattr(importlib.import_module(pkg), "__version__", "unknown")
    u = platform.uname()
    # A cluster run (--profile) has no --cores: each job asks for its own.
    cores = workflow.cores if workflow.nodes is None else "per-job"
    return {"uname": f"{u.system} {u.release} {u.machine}", "cpu": cpu, "cores": cores,
            "python": platform.python_version(), **versions}


def _unique(paths):
    return list(dict.fromkeys(p for p in paths if p))


def _tex(csv_path):
    return csv_path[: -len(".csv")] + ".tex"


REPORT_TABLES = _unique([it["output"] for it in REPORT_ITEMS if it["kind"] == "table"]
                        + [p for it in REPORT_ITEMS for p in it["extra"]])


rule table_tex:
    input:
        csv="results/tables/{table}.csv",
    output:
        tex="results/tables/{table}.tex",
    log:
        "logs/tables/{table}_tex.log",
    benchmark:
        "benchmarks/tables/{table}_tex.tsv"
    wildcard_constraints:
        table="[a-z0-9_]+",
    script:
        "../scripts/latex_table.py"


rule report:
    input:
        tables=REPORT_TABLES,
        tex=[_tex(p) for p in REPORT_TABLES],
        figures=_unique(it["output"] for it in REPORT_ITEMS if it["kind"] == "figure"),
        summaries=_unique(it["summary"] for it in REPORT_ITEMS),
        published=_unique(it["published"] for it in REPORT_ITEMS),
        benchmarks=_unique(b for it in REPORT_ITEMS for b in it["benchmarks"]),
        runs=_unique(r for it in REPORT_ITEMS for r in it["runs"]),
    output:
        md=f"{config['report_dir']}/reproduction.md",
        html=f"{config['report_dir']}/reproduction.html",
        figures=directory(f"{config['report_dir']}/figures"),
        tables=directory(f"{config['report_dir']}/tables"),
        captions=directory(f"{config['report_dir']}/captions"),
    log:
        "logs/report.log",
    benchmark:
        "benchmarks/report.tsv"
    params:
        manifest=REPORT_ITEMS,
        profile=config["profile"],
        config=yaml.safe_dump(config, sort_keys=False, allow_unicode=True),
        machine=machine_info(),
    script:
        "../scripts/report.py"
