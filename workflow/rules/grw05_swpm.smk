"""GRW05 Examples 7-9 with weighted particles (SWPM; GRW05 Remark 10): the deep tails.

Raw runs:  results/grw05_swpm/<experiment>/N=<ensembles>/n=<particles>/run.h5 (dsmc.weights: swpm,
           kappa and max_particles of config grw05.tails.swpm, importance splitting beyond
           split_radius with the theory tail's a and b; the physics of the experiment run to
           `duration` times its t_end, the steady histogram averaged over (t_end, duration t_end]
           at `rows` times; 128 shells out to tails.swpm.radius)
Items:     figures grw05_tail_swpm_ex{7,8,9} (ln f against r for both methods, b(r) of both) with
           their summaries, which the tail-exponent table takes (columns b_swpm ... depth_swpm), in
           the report section "Weighted particles".
"""

SWPM = GRW05["tails"]["swpm"]
SWPM_PAPER = "Weighted particles"
SWPM_EXAMPLES = ("ex7", "ex8", "ex9")
# The importance check: the same example again with an importance function of another shape.
SWPM_CHECK = SWPM["check"]["example"] + "_check"
SWPM_RUNS = SWPM_EXAMPLES + (SWPM_CHECK,)


def grw05_swpm_runs(ex):
    """The SWPM run of experiment `ex` (one per example)."""
    return expand("results/grw05_swpm/{ex}/N={N}/n={n}/run.h5", ex=ex, N=SWPM["ensembles"], n=SWPM["particles"])


def grw05_swpm_split(ex, power=None):
    """dsmc.weights.split of experiment `ex` (granboltz.theory.tail_theory.importance_split): the theory
    tail as importance function from split_radius out to the histogram radius R, or the importance
    check's exp(-a' r^power)."""
    from granboltz.theory.tail_theory import importance_split

    e = GRW05[ex]
    return importance_split(float(e["kernel"]["lambda"]), float(e["beta"]), float(e["gamma"]),
                            float(e["kernel"]["C"]), float(SWPM["radius"][ex]), SWPM["split_radius"][ex], power, d=3)


def grw05_swpm_run_config(wildcards):
    """Run config of results/grw05_swpm/{ex}/N={N}/n={n}: the experiment's physics run to
    `duration` t_end, observed `rows` times in the steady window (t_end, duration t_end], the SWPM
    weights with importance splitting, and the wide histogram."""
    ex = wildcards.ex.removesuffix("_check")
    e = GRW05[ex]
    power = SWPM["check"]["power"] if wildcards.ex == SWPM_CHECK else None
    weights = {"method": "swpm", "kappa": SWPM["kappa"], "max_particles": int(SWPM["max_particles"]),
               "reduction": SWPM["reduction"], "split": grw05_swpm_split(ex, power)}
    histogram = {"shells": int(e["histogram"]["shells"]), "radius": float(SWPM["radius"][ex])}
    label = f"grw05_swpm/{wildcards.ex}/n={wildcards.n}"
    t_end = float(e["t_end"])
    window = (float(SWPM["duration"]) - 1.0) * t_end
    return dsmc_run_config(label, e, wildcards.N, wildcards.n, t_end + window, window / int(SWPM["rows"]),
                           scheme="nosplit", histogram=histogram, weights=weights, steady_from=t_end)


def swpm_mem_mb(wildcards, threads):
    """Memory of an SWPM run: as run_mem_mb, with the particle cap in place of n."""
    extra = int(SWPM["max_particles"]) * threads * config["mem_bytes_per_particle"]
    return config["run_mem_mb"] + math.ceil(extra / 1e6)


localrules:
    grw05_swpm_run_config,


use rule run_config as grw05_swpm_run_config with:
    output:
        yaml="results/grw05_swpm/{ex}/N={N}/n={n}/run.yaml",
    log:
        "logs/grw05_swpm/{ex}/N={N}/n={n}/run_config.log",
    wildcard_constraints:
        ex=_one_of(SWPM_RUNS),
    params:
        run=grw05_swpm_run_config,


use rule run as grw05_swpm_run with:
    input:
        config=rules.grw05_swpm_run_config.output.yaml,
        granboltz=config["granboltz"],
    output:
        h5="results/grw05_swpm/{ex}/N={N}/n={n}/run.h5",
    log:
        "logs/grw05_swpm/{ex}/N={N}/n={n}/run.log",
    benchmark:
        "benchmarks/grw05_swpm/{ex}/N={N}/n={n}/run.tsv"
    wildcard_constraints:
        ex=_one_of(SWPM_RUNS),
    resources:
        mem_mb=swpm_mem_mb,


# ln f against r for both methods and b(r) of both, one figure per example.
for _ex in SWPM_EXAMPLES:

    rule:
        name:
            f"grw05_tail_swpm_{_ex}"
        input:
            swpm=grw05_swpm_runs(_ex),
            constant=grw05_runs(_ex),
        output:
            png=report(f"figures/grw05_tail_swpm_{_ex}.png", caption=item_caption(f"grw05_tail_swpm_{_ex}"),
                       category="Weighted particles"),
            pdf=f"figures/grw05_tail_swpm_{_ex}.pdf",
            summary=f"results/figures/grw05_tail_swpm_{_ex}.json",
        log:
            f"logs/figures/grw05_tail_swpm_{_ex}.log",
        benchmark:
            f"benchmarks/figures/grw05_tail_swpm_{_ex}.tsv"
        params:
            tails=GRW05["tails"],
            example=int(_ex[2:]),
        script:
            "../scripts/tail_swpm.py"


for _ex, _b in (("ex7", "1"), ("ex8", "1.5"), ("ex9", "1.25")):
    _rule = getattr(rules, f"grw05_tail_swpm_{_ex}")
    report_item(SWPM_PAPER, f"Tail Ex. {_ex[2:]}", _rule, "figure", _rule.output.png,
                f"(not in the paper; GRW05 Remark 10) ln f against r with weighted particles (SWPM) and "
                f"constant weights, and b(r) of both against theory b = {_b}", runs=_rule.input.swpm,
                run_rule=rules.grw05_swpm_run, summary=_rule.output.summary)


# The importance check (docs/config.md: the importance function sets the variance, not the mean):
# b, a and the depth of the same example with the theory importance and with another shape.
rule grw05_tail_swpm_check:
    input:
        theory=grw05_swpm_runs(SWPM["check"]["example"]),
        check=grw05_swpm_runs(SWPM_CHECK),
    output:
        png=report("figures/grw05_tail_swpm_check.png", caption=item_caption("grw05_tail_swpm_check"),
                   category="Weighted particles"),
        pdf="figures/grw05_tail_swpm_check.pdf",
        summary="results/figures/grw05_tail_swpm_check.json",
    log:
        "logs/figures/grw05_tail_swpm_check.log",
    benchmark:
        "benchmarks/figures/grw05_tail_swpm_check.tsv"
    params:
        tails=GRW05["tails"],
        example=int(SWPM["check"]["example"][2:]),
        theory_split=grw05_swpm_split(SWPM["check"]["example"]),
        check_split=grw05_swpm_split(SWPM["check"]["example"], SWPM["check"]["power"]),
    script:
        "../scripts/tail_swpm_check.py"


report_item(SWPM_PAPER, "Importance check", rules.grw05_tail_swpm_check, "figure",
            rules.grw05_tail_swpm_check.output.png,
            f"(not in the paper) Example {SWPM['check']['example'][2:]} with an importance function of "
            f"another shape (r^{SWPM['check']['power']:g} instead of the theory's): b and a must not depend on it",
            runs=rules.grw05_tail_swpm_check.input.check, run_rule=rules.grw05_swpm_run,
            summary=rules.grw05_tail_swpm_check.output.summary)
