"""GRW05: Gamba, Rjasanow, Wagner, Math. Comput. Modelling 42 (2005) 683-700.

Raw runs:  results/grw05/<experiment>/N=<ensembles>/n=<particles>/run.h5
Items:     Tables 1-2 and Figs. 1-2 (Examples 3-4, §5.2), Fig. 3 (Example 5, hard spheres),
           Figs. 4-7 and the tail exponents (Examples 7-9, §5.3).
"""

GRW05 = config["grw05"]
# Experiments whose runs are split into shards of ensembles (`shards` > 1) and merged.
GRW05_EXPERIMENTS = [k for k, v in GRW05.items() if isinstance(v, dict) and "ensembles" in v]
GRW05_SHARDED = [k for k in GRW05_EXPERIMENTS if GRW05[k].get("shards", 1) > 1]


def _one_of(names):
    """A wildcard constraint matching exactly these names (nothing when empty)."""
    return "|".join(names) if names else "(?!x)x"


def grw05_shards(wildcards):
    """The shard outputs of a sharded run."""
    S = GRW05[wildcards.ex]["shards"]
    return expand(rules.grw05_shard.output.h5, i=range(S), S=S, allow_missing=True)


def grw05_runs(ex, particles=None):
    """The HDF5 outputs of experiment `ex` for each n in `particles` (default: all of ex)."""
    particles = GRW05[ex]["particles"] if particles is None else particles
    runs = expand("results/grw05/{ex}/N={N}/n={n}/run.h5", ex=ex, N=GRW05[ex]["ensembles"], n=particles)
    if ex in GRW05_SHARDED:
        S = GRW05[ex]["shards"]
        for run, n in zip(runs, particles):
            base = f"benchmarks/grw05/{ex}/N={GRW05[ex]['ensembles']}/n={n}"
            SHARDED_RUN_BENCHMARKS[run] = [f"{base}/shard={i}of{S}.tsv" for i in range(S)] + [
                f"{base}/merge.tsv"
            ]
    return runs


def grw05_run_config(wildcards):
    """Run config of results/grw05/{ex}/N={N}/n={n}: the experiment's keys, with its histogram."""
    e = GRW05[wildcards.ex]
    extra = {"histogram": dict(e["histogram"])} if "histogram" in e else {}
    if "moments" in e:
        extra["moments"] = int(e["moments"])
    label = f"grw05/{wildcards.ex}/n={wildcards.n}"
    return dsmc_run_config(label, e, wildcards.N, wildcards.n, e["t_end"], e["observe_every"],
                           scheme=e.get("scheme", "nosplit"), **extra)


localrules:
    grw05_run_config,


use rule run_config as grw05_run_config with:
    output:
        yaml="results/grw05/{ex}/N={N}/n={n}/run.yaml",
    log:
        "logs/grw05/{ex}/N={N}/n={n}/run_config.log",
    params:
        run=grw05_run_config,


use rule run as grw05_run with:
    input:
        config=rules.grw05_run_config.output.yaml,
        granboltz=config["granboltz"],
    output:
        h5="results/grw05/{ex}/N={N}/n={n}/run.h5",
    log:
        "logs/grw05/{ex}/N={N}/n={n}/run.log",
    benchmark:
        "benchmarks/grw05/{ex}/N={N}/n={n}/run.tsv"
    wildcard_constraints:
        ex=_one_of([k for k in GRW05_EXPERIMENTS if k not in GRW05_SHARDED]),


# Sharded runs: one job per shard of ensembles (a cluster runs them side by side), then a merge
# that is identical, bit for bit, to the unsharded run.
rule grw05_shard:
    input:
        config=rules.grw05_run_config.output.yaml,
        granboltz=config["granboltz"],
    output:
        h5=temp("results/grw05/{ex}/N={N}/n={n}/shard={i}of{S}.h5"),
    log:
        "logs/grw05/{ex}/N={N}/n={n}/shard={i}of{S}.log",
    benchmark:
        "benchmarks/grw05/{ex}/N={N}/n={n}/shard={i}of{S}.tsv"
    wildcard_constraints:
        ex=_one_of(GRW05_SHARDED),
        i=r"\d+",
        S=r"\d+",
    params:
        checkpoint_seconds=config["checkpoint_seconds"],
    threads: run_threads
    resources:
        mem_mb=run_mem_mb,
    # exec: no shell between Snakemake and the simulator, which alone answers SIGTERM (checkpoint)
    shell:
        "exec {input.granboltz} run {input.config} -o {output.h5} --threads {threads}"
        " --set shard.index={wildcards.i} --set shard.count={wildcards.S}"
        " --set checkpoint.every_seconds={params.checkpoint_seconds} > {log} 2>&1"


rule grw05_merge:
    input:
        shards=grw05_shards,
        granboltz=config["granboltz"],
    output:
        h5="results/grw05/{ex}/N={N}/n={n}/run.h5",
    log:
        "logs/grw05/{ex}/N={N}/n={n}/merge.log",
    benchmark:
        "benchmarks/grw05/{ex}/N={N}/n={n}/merge.tsv"
    wildcard_constraints:
        ex=_one_of(GRW05_SHARDED),
    shell:
        "{input.granboltz} merge {input.shards} -o {output.h5} > {log} 2>&1"


# ----------------------------------------------------------------------------- Tables 1, 2
rule grw05_table1:
    input:
        runs=grw05_runs("ex3"),
    output:
        csv=report("results/tables/grw05_table1.csv", caption=item_caption("grw05_table1"), category="GRW05"),
    log:
        "logs/tables/grw05_table1.log",
    benchmark:
        "benchmarks/tables/grw05_table1.tsv"
    script:
        "../scripts/grw05_convergence_table.py"


rule grw05_table2:
    input:
        runs=grw05_runs("ex4"),
    output:
        csv=report("results/tables/grw05_table2.csv", caption=item_caption("grw05_table2"), category="GRW05"),
    log:
        "logs/tables/grw05_table2.log",
    benchmark:
        "benchmarks/tables/grw05_table2.tsv"
    script:
        "../scripts/grw05_convergence_table.py"


report_item("GRW05", "Table 1", rules.grw05_table1, "table", rules.grw05_table1.output.csv,
            "Example 3 (λ = 0, β = 1): E_max of T(t) against eq. (34) falls like 1/n (CF ≈ 4); ‖V‖∞ stays small",
            runs=rules.grw05_table1.input.runs, run_rule=rules.grw05_run, compare="convergence",
            published="grw05_table1")
report_item("GRW05", "Table 2", rules.grw05_table2, "table", rules.grw05_table2.output.csv,
            "Example 4 (λ = 0, β = 1/8, T decreasing to 1/3): E_max against eq. (36), CF ≈ 4",
            runs=rules.grw05_table2.input.runs, run_rule=rules.grw05_run, compare="convergence",
            published="grw05_table2")


# ----------------------------------------------------------------------------- Figs. 1, 2
rule grw05_fig1:
    input:
        runs=grw05_runs("ex3", GRW05["fig1"]["particles"]),
    output:
        png=report("figures/grw05_fig1.png", caption=item_caption("grw05_fig1"), category="GRW05"),
        pdf="figures/grw05_fig1.pdf",
        summary="results/figures/grw05_fig1.json",
    log:
        "logs/figures/grw05_fig1.log",
    benchmark:
        "benchmarks/figures/grw05_fig1.tsv"
    params:
        t_range=GRW05["fig1"]["t_range"],
    script:
        "../scripts/temperature_bands.py"


rule grw05_fig2:
    input:
        runs=grw05_runs("ex4", GRW05["fig2"]["particles"]),
    output:
        png=report("figures/grw05_fig2.png", caption=item_caption("grw05_fig2"), category="GRW05"),
        pdf="figures/grw05_fig2.pdf",
        summary="results/figures/grw05_fig2.json",
    log:
        "logs/figures/grw05_fig2.log",
    benchmark:
        "benchmarks/figures/grw05_fig2.tsv"
    params:
        t_range=GRW05["fig2"]["t_range"],
    script:
        "../scripts/temperature_bands.py"


for _fig, _what in (("1", "Example 3: confidence bands (eq. 31) of T(t) against eq. (34) on [2, 8], n = 64 … 4096"),
                    ("2", "Example 4: confidence bands of T(t) against eq. (36) on [2, 8], n = 64 … 4096")):
    _rule = getattr(rules, f"grw05_fig{_fig}")
    report_item("GRW05", f"Fig. {_fig}", _rule, "figure", _rule.output.png, _what, runs=_rule.input.runs,
                run_rule=rules.grw05_run, summary=_rule.output.summary)


# ----------------------------------------------------------------------------- Fig. 3
rule grw05_fig3:
    input:
        runs=grw05_runs("ex5"),
    output:
        png=report("figures/grw05_fig3.png", caption=item_caption("grw05_fig3"), category="GRW05"),
        pdf="figures/grw05_fig3.pdf",
        summary="results/figures/grw05_fig3.json",
    log:
        "logs/figures/grw05_fig3.log",
    benchmark:
        "benchmarks/figures/grw05_fig3.tsv"
    params:
        t_range=GRW05["fig3"]["t_range"],
    script:
        "../scripts/temperature_curves.py"


report_item("GRW05", "Fig. 3", rules.grw05_fig3, "figure", rules.grw05_fig3.output.png,
            "Example 5 (hard spheres): T(t) for n = 64 … 4096 (from above) converges as n grows",
            runs=rules.grw05_fig3.input.runs, run_rule=rules.grw05_run, summary=rules.grw05_fig3.output.summary)


# ----------------------------------------------------------------------------- Fig. 4
rule grw05_fig4:
    input:
        runs=grw05_runs("ex7"),
    output:
        png=report("figures/grw05_fig4.png", caption=item_caption("grw05_fig4"), category="GRW05"),
        pdf="figures/grw05_fig4.pdf",
        summary="results/figures/grw05_fig4.json",
    log:
        "logs/figures/grw05_fig4.log",
    benchmark:
        "benchmarks/figures/grw05_fig4.tsv"
    params:
        left=GRW05["fig4"]["left"],
        right=GRW05["fig4"]["right"],
    script:
        "../scripts/histograms.py"


report_item("GRW05", "Fig. 4", rules.grw05_fig4, "figure", rules.grw05_fig4.output.png,
            "Example 7: initial (thick) and final (thin) histograms f_k, r ∈ [0, 10] and the overpopulated tail r ∈ [2, 10]",
            runs=rules.grw05_fig4.input.runs, run_rule=rules.grw05_run, summary=rules.grw05_fig4.output.summary)


# ----------------------------------------------------------------------------- local exponents
# b(r) of each tail example, one job each (they run side by side).
for _ex in ("ex7", "ex8", "ex9"):

    rule:
        name:
            f"grw05_tail_local_{_ex}"
        input:
            runs=grw05_runs(_ex),
        output:
            png=report(f"figures/grw05_tail_local_{_ex}.png", caption=item_caption(f"grw05_tail_local_{_ex}"),
                       category="GRW05"),
            pdf=f"figures/grw05_tail_local_{_ex}.pdf",
            summary=f"results/figures/grw05_tail_local_{_ex}.json",
        log:
            f"logs/figures/grw05_tail_local_{_ex}.log",
        benchmark:
            f"benchmarks/figures/grw05_tail_local_{_ex}.tsv"
        params:
            tails=GRW05["tails"],
            example=int(_ex[2:]),
        script:
            "../scripts/tail_local.py"


# ----------------------------------------------------------------------------- tail exponents
rule grw05_tail_exponents:
    input:
        ex7=grw05_runs("ex7"),
        ex8=grw05_runs("ex8"),
        ex9=grw05_runs("ex9"),
        local=[getattr(rules, f"grw05_tail_local_{ex}").output.summary for ex in ("ex7", "ex8", "ex9")],
        swpm=[f"results/figures/grw05_tail_swpm_{ex}.json" for ex in ("ex7", "ex8", "ex9")],  # grw05_swpm.smk
    output:
        csv=report("results/tables/grw05_tail_exponents.csv", caption=item_caption("grw05_tail_exponents"), category="GRW05"),
        windows="results/tables/grw05_tail_windows.csv",
    log:
        "logs/tables/grw05_tail_exponents.log",
    benchmark:
        "benchmarks/tables/grw05_tail_exponents.tsv"
    params:
        tails=GRW05["tails"],
    script:
        "../scripts/tail_exponents.py"


# ----------------------------------------------------------------------------- Figs. 5-7
for _fig, _ex, _what in (
    (5, "ex7", "Example 7 (λ = 0): (x_k, y_k) of eq. (38), k0 = 1, with y = x − 2, 1.25x − 2, 1.5x − 2; fitted b = 0.998"),
    (6, "ex8", "Example 8 (hard spheres): (x_k, y_k) with y = x − 3, 1.25x − 3, 1.5x − 3; fitted b = 1.474"),
    (7, "ex9", "Example 9 (λ = 1/2): (x_k, y_k) with y = x − 2, 1.25x − 2, 1.5x − 2; fitted b = 1.266"),
):

    rule:
        name:
            f"grw05_fig{_fig}"
        input:
            runs=grw05_runs(_ex),
        output:
            png=report(f"figures/grw05_fig{_fig}.png", caption=item_caption(f"grw05_fig{_fig}"), category="GRW05"),
            pdf=f"figures/grw05_fig{_fig}.pdf",
            summary=f"results/figures/grw05_fig{_fig}.json",
        log:
            f"logs/figures/grw05_fig{_fig}.log",
        benchmark:
            f"benchmarks/figures/grw05_fig{_fig}.tsv"
        params:
            tails=GRW05["tails"],
            guide_intercept=GRW05["tails"]["guide_intercepts"][_ex],
            example=int(_ex[2:]),
        script:
            "../scripts/tail_plot.py"

    _rule = getattr(rules, f"grw05_fig{_fig}")
    report_item("GRW05", f"Fig. {_fig}", _rule, "figure", _rule.output.png, _what, runs=_rule.input.runs,
                run_rule=rules.grw05_run, summary=_rule.output.summary)


# The tail section of the report: Figs. 5-7, the paper's fit (published vs ours, with the theory a,
# b and the local exponents), the Ex. 7 moments, the local-exponent figures with their verdicts.
report_item("GRW05", "Tail exponents", rules.grw05_tail_exponents, "table", rules.grw05_tail_exponents.output.csv,
            "least-squares slope b of (x_k, y_k), eq. (38), on x ∈ [4.25, 4.6]: 0.998 (λ = 0), 1.474 (λ = 1), 1.266 (λ = 1/2)",
            runs=[*rules.grw05_tail_exponents.input.ex7, *rules.grw05_tail_exponents.input.ex8,
                  *rules.grw05_tail_exponents.input.ex9], run_rule=rules.grw05_run, compare="tails",
            published="grw05_tail_exponents", extra=[rules.grw05_tail_exponents.output.windows])


# ----------------------------------------------------------------------------- Ex. 7 moments
rule grw05_ex7_moments:
    input:
        runs=grw05_runs("ex7"),
    output:
        csv=report("results/tables/grw05_ex7_moments.csv", caption=item_caption("grw05_ex7_moments"),
                   category="GRW05"),
        amplitude="results/tables/grw05_ex7_amplitude.csv",
    log:
        "logs/tables/grw05_ex7_moments.log",
    benchmark:
        "benchmarks/tables/grw05_ex7_moments.tsv"
    params:
        moments=8,  # M_2 ... M_16 against the exact hierarchy
        pmax=40,  # the amplitude from the growth of M_2p up to p = 40 (at least 30 are needed)
    script:
        "../scripts/grw05_ex7_moments.py"


report_item("GRW05", "Ex. 7 moments", rules.grw05_ex7_moments, "table", rules.grw05_ex7_moments.output.csv,
            "(not in the paper) M_2 … M_16 of the Example 7 final state against the exact moment hierarchy "
            "for λ = 0, and the tail amplitude a = √(ν/β) from the growth of the exact moments",
            runs=rules.grw05_ex7_moments.input.runs, run_rule=rules.grw05_run, compare="ex7_moments",
            extra=[rules.grw05_ex7_moments.output.amplitude])
for _ex, _b in (("ex7", "1"), ("ex8", "1.5"), ("ex9", "1.25")):
    _rule = getattr(rules, f"grw05_tail_local_{_ex}")
    report_item("GRW05", f"Tail local exponent Ex. {_ex[2:]}", _rule, "figure", _rule.output.png,
                f"(not in the paper) local exponent b(r) with its band against theory b = {_b}, the "
                "paper's window and where the data run out", runs=_rule.input.runs, run_rule=rules.grw05_run,
                summary=_rule.output.summary)


GRW05_OUTPUTS = [item["output"] for item in REPORT_ITEMS if item["paper"] == "GRW05"]
