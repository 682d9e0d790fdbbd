"""Config validation and helpers shared by the rule files (the Snakefile includes this first).

Also the registry of report items: every rule file calls report_item(...) for each table and
figure it makes; report.smk builds paper/reproduction.{md,html} from the registry, so a paper's
rule file (e.g. tv06.smk) adds its items to the report just by registering them.
"""

import math
import zlib

from snakemake.utils import validate


validate(config, schema="../schemas/config.schema.yaml")


def _whole(x, unit):
    """Whether x is a whole multiple of unit (to 1e-9 relative)."""
    q = x / unit
    return abs(q - round(q)) <= 1e-9 * max(1.0, abs(q))


def check_config(cfg):
    """Cross-key checks the schema cannot express; raise ValueError naming the offending key."""
    for name, item in cfg["grw05"].items():
        if "observe_every" in item and not _whole(item["t_end"], item["observe_every"]):
            raise ValueError(f"grw05.{name}: t_end must be a whole multiple of observe_every")
    for fig, ex in (("fig1", "ex3"), ("fig2", "ex4")):
        t_min, t_max = cfg["grw05"][fig]["t_range"]
        if not t_min < t_max <= cfg["grw05"][ex]["t_end"]:
            raise ValueError(f"grw05.{fig}.t_range: need t_min < t_max <= grw05.{ex}.t_end")
        if not set(cfg["grw05"][fig]["particles"]) <= set(cfg["grw05"][ex]["particles"]):
            raise ValueError(f"grw05.{fig}.particles: must be among grw05.{ex}.particles")
    for ex in ("ex7", "ex8", "ex9"):
        if "histogram" not in cfg["grw05"][ex] or len(cfg["grw05"][ex]["particles"]) != 1:
            raise ValueError(f"grw05.{ex}: a tail example needs a histogram and exactly one n")
    tails = cfg["grw05"]["tails"]
    for window in [tails["fit_window"]] + tails["windows"]:
        if not window[0] < window[1]:
            raise ValueError(f"grw05.tails: window {window} must have x_min < x_max")
    rw = cfg["rw05"]
    for fig in ("fig1", "fig2"):
        if not set(rw[fig]["particles"]) <= set(rw["transient"]["particles"]):
            raise ValueError(f"rw05.{fig}.particles: must be among rw05.transient.particles")
        t_min, t_max = rw[fig]["t_range"]
        if not t_min < t_max <= rw["transient"]["t_end"]:
            raise ValueError(f"rw05.{fig}.t_range: need t_min < t_max <= rw05.transient.t_end")
    if len(rw["crit"]["particles"]) != len(rw["crit"]["ensembles"]):
        raise ValueError("rw05.crit: particles and ensembles must have the same length")
    for name in ("transient", "crit", "crit_schemes", "steady"):
        if not _whole(rw[name]["t_end"], rw[name]["observe_every"]):
            raise ValueError(f"rw05.{name}: t_end must be a whole multiple of observe_every")
    checks = [("timestep", K, None) for K in rw["timestep"]["steps"]]
    checks += [("crit_schemes", rw["crit_schemes"]["steps"], rw["crit_schemes"]["observe_every"])]
    checks += [("steady", K, rw["steady"]["observe_every"]) for K in rw["steady"]["euler_steps"]]
    checks += [("steady", K, rw["steady"]["observe_every"]) for K in rw["steady"]["strang_steps"]]
    checks += [("steady", rw["hot"]["steps"], rw["steady"]["observe_every"])]
    checks += [("steady", rw["steady"]["replica_euler_steps"], rw["steady"]["observe_every"])]
    for name, K, every in checks:
        dt = rw["dt_unit"] / K
        if not _whole(rw[name]["t_end"], dt) or (every is not None and not _whole(every, dt)):
            raise ValueError(f"rw05.{name}: K = {K} gives dt = {dt}, which must divide t_end and observe_every")
    if not rw["steady"]["steady_from"] < rw["steady"]["t_end"]:
        raise ValueError("rw05.steady: need steady_from < t_end")


check_config(config)


wildcard_constraints:
    ex="ex[0-9]+",
    exp="[a-z_]+|replica_[0-9]+",
    scheme="nosplit|(euler|strang)_K=[0-9]+",
    N="[0-9]+",
    n="[0-9]+",


def run_seed(label):
    """Seed of one run: the base seed plus crc32(label), e.g. label "grw05/ex3/n=64".

    The simulator keys its random streams by (seed, ensemble, consumer), so runs with different
    labels draw independent streams, a rerun is identical, and the first N ensembles of a run do
    not depend on how many ensembles it has.
    """
    return config["seed"] + zlib.crc32(label.encode())


def run_threads(wildcards):
    """Threads of a run: config threads, but never more than its N ensembles (one per thread)."""
    return max(1, min(config["threads"], int(wildcards.N)))


def run_mem_mb(wildcards, threads):
    """Memory of a run: run_mem_mb plus mem_bytes_per_particle per particle and thread."""
    extra = int(wildcards.n) * threads * config["mem_bytes_per_particle"]
    return config["run_mem_mb"] + math.ceil(extra / 1e6)


# The run-config + run pair every rule file uses, through `use rule run_config as <paper>_run_config
# with:` and `use rule run as <paper>_run with:` giving its paths, params and constraints. Its own
# paths have no wildcards and no rule asks for them, so the pair itself never makes a job.
localrules:
    run_config,


rule run_config:
    output:
        yaml="results/.template/run.yaml",
    log:
        "logs/.template/run_config.log",
    script:
        "../scripts/write_run_config.py"


rule run:
    input:
        config=rules.run_config.output.yaml,
        granboltz=config["granboltz"],
    output:
        h5="results/.template/run.h5",
    log:
        "logs/.template/run.log",
    benchmark:
        "benchmarks/.template/run.tsv"
    threads: run_threads
    resources:
        mem_mb=run_mem_mb,
    shell:
        "{input.granboltz} run {input.config} -o {output.h5} --threads {threads} > {log} 2>&1"


def dsmc_run_config(label, physics, N, n, t_end, observe_every, **dsmc):
    """The simulator's run config (a dict, written as YAML): physics (alpha, or restitution for
    another law; beta, gamma, kernel, temperature0, majorant_update) and timing, plus any further
    dsmc keys (scheme, steps, histogram, steady_from)."""
    if "histogram" in dsmc:
        # The papers' histograms are of |v| (GRW05 eq. 37), not of |v - V(t)|.
        dsmc["histogram"] = {"center": "origin", **dsmc["histogram"]}
    return {
        "model": "dsmc",
        "seed": run_seed(label),
        "ensembles": int(N),
        "dsmc": {
            "particles": int(n),
            "scheme": dsmc.pop("scheme", "nosplit"),
            # the simulator takes one of the two (restitution in alpha's place keeps the key order)
            **({"restitution": physics["restitution"]} if "restitution" in physics else {"alpha": physics["alpha"]}),
            "beta": physics["beta"],
            "gamma": physics["gamma"],
            "kernel": {"lambda": physics["kernel"]["lambda"], "C": physics["kernel"]["C"]},
            "initial": {"temperature": physics.get("temperature0", 1.0)},
            "t_end": t_end,
            "observe_every": observe_every,
            "majorant_update": physics.get("majorant_update", "paper"),
            # The papers' steady intervals count every (ensemble, t_m) sample as independent:
            # asked for explicitly so that the reproduction keeps its bits and tables.
            **({"steady_ci": "independent"} if "steady_from" in dsmc else {}),
            **dsmc,
        },
    }


# Runs made from shards: run output -> the benchmark files of its shard and merge jobs.
SHARDED_RUN_BENCHMARKS = {}


def run_benchmarks(run_rule, runs):
    """The benchmark files of `runs` (outputs h5 of run_rule), from the rule's own patterns."""
    from snakemake.io import glob_wildcards

    bench = []
    for h5 in runs:
        if str(h5) in SHARDED_RUN_BENCHMARKS:
            bench += SHARDED_RUN_BENCHMARKS[str(h5)]
            continue
        wc = glob_wildcards(run_rule.output.h5, files=[h5])
        bench += expand(run_rule.benchmark, zip, **wc._asdict())
    return bench


# ----------------------------------------------------------------------------- report registry
REPORT_ITEMS = []


def item_caption(rule):
    """The Snakemake-report caption of the outputs of `rule`: written by rule report from the
    descriptions registered with report_item(), so that each is written once."""
    return os.path.abspath(f"{config['report_dir']}/captions/{rule}.rst")


def report_item(paper, item, rule, kind, outputs, what, runs=(), run_rule=None, compare=None,
                published=None, summary=None, extra=()):
    """Register a table or figure for paper/reproduction.{md,html}.

    paper, item: e.g. "GRW05", "Table 1"; rule: the RuleProxy that makes it (its name and
    benchmark go to the report); kind: "table" or "figure"; outputs: the csv (table) or the
    png (figure) shown; what: one line on what the paper shows; runs: the simulator outputs
    behind it (their benchmarks are its run time; run_rule makes them); compare: name of the
    comparison in granboltz.report (tables with published numbers); published: name of the
    published CSV in config.published; summary: JSON written by a figure rule with the line
    "ours"; extra: further generated CSVs shown with the item (e.g. a window table).
    """
    bench = [rule.benchmark] + (run_benchmarks(run_rule, runs) if runs else [])
    REPORT_ITEMS.append(  # plain strings only: the registry is a param of rule report (pickled)
        {
            "paper": paper,
            "item": item,
            "rule": rule.rule.name,
            "kind": kind,
            "output": str(outputs),
            "what": what,
            "runs": [str(r) for r in runs],
            "benchmarks": [str(b) for b in bench],
            "compare": compare,
            "published": f"{config['published']}/{published}.csv" if published else None,
            "summary": None if summary is None else str(summary),
            "extra": [str(e) for e in extra],
        }
    )
