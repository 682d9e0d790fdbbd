"""RW05: Rjasanow, Wagner, Time splitting error in DSMC schemes for the inelastic Boltzmann
equation, Preprint 158, Universität des Saarlandes (2005).

Raw runs:  results/rw05/<experiment>/<scheme>/N=<ensembles>/n=<particles>/run.h5, with
           <scheme> = nosplit, euler_K=<K> or strang_K=<K> (time step dt = dt_unit / K)
Items:     Tables 1-2, Figs. 1-4 (transient, §4.1); Tables 3-6 and the effort model (steady
           state, §4.2); our check of the steady-state confidence intervals by independent repeats
           (experiments replica_<i>: the steady runs with other seeds).
"""

RW05 = config["rw05"]
# experiment -> config block with its timing (t_end, observe_every, ...); hot = steady, other beta
RW05_TIMING = {"transient": "transient", "timestep": "timestep", "crit": "crit",
               "crit_schemes": "crit_schemes", "steady": "steady", "hot": "steady"}


def rw05_runs(exp, schemes, N, particles):
    """The HDF5 outputs of experiment `exp` for every scheme token and n (one N)."""
    return expand(rules.rw05_run.output.h5, exp=exp, scheme=schemes, N=N, n=particles)


def rw05_run_config(wildcards):
    """Run config of results/rw05/{exp}/{scheme}/N={N}/n={n} from rw05.physics and the timing
    of the experiment; splitting schemes get steps = t_end / dt with dt = dt_unit / K."""
    timing = RW05[RW05_TIMING.get(wildcards.exp, "steady")]  # replica_<i>: as steady
    physics = dict(RW05["physics"])
    if wildcards.exp == "hot":
        physics["beta"] = RW05["hot"]["beta"]
    extra, every = {}, timing.get("observe_every")
    if wildcards.scheme != "nosplit":
        scheme, K = wildcards.scheme.split("_K=")
        dt = RW05["dt_unit"] / int(K)
        extra = {"scheme": scheme, "steps": round(timing["t_end"] / dt)}
        every = dt if every is None else every  # Table 2: observe at every time step
    if "steady_from" in timing:
        extra["steady_from"] = timing["steady_from"]
    label = f"rw05/{wildcards.exp}/{wildcards.scheme}/n={wildcards.n}"
    return dsmc_run_config(label, physics, wildcards.N, wildcards.n, timing["t_end"], every, **extra)


localrules:
    rw05_run_config,


use rule run_config as rw05_run_config with:
    output:
        yaml="results/rw05/{exp}/{scheme}/N={N}/n={n}/run.yaml",
    log:
        "logs/rw05/{exp}/{scheme}/N={N}/n={n}/run_config.log",
    params:
        run=rw05_run_config,


use rule run as rw05_run with:
    input:
        config=rules.rw05_run_config.output.yaml,
        granboltz=config["granboltz"],
    output:
        h5="results/rw05/{exp}/{scheme}/N={N}/n={n}/run.h5",
    log:
        "logs/rw05/{exp}/{scheme}/N={N}/n={n}/run.log",
    benchmark:
        "benchmarks/rw05/{exp}/{scheme}/N={N}/n={n}/run.tsv"


def _steady(scheme, K=None, exp="steady"):
    s = RW05["steady"]
    return rw05_runs(exp, scheme if K is None else [f"{scheme}_K={k}" for k in K], s["ensembles"], s["particles"])


TR, TS, CS = RW05["transient"], RW05["timestep"], RW05["crit_schemes"]


# ----------------------------------------------------------------------------- Tables 1, 2
rule rw05_table1:
    input:
        runs=rw05_runs("transient", "nosplit", TR["ensembles"], TR["particles"]),
    output:
        csv=report("results/tables/rw05_table1.csv", caption=item_caption("rw05_table1"), category="RW05"),
    log:
        "logs/tables/rw05_table1.log",
    benchmark:
        "benchmarks/tables/rw05_table1.tsv"
    script:
        "../scripts/rw05_convergence_table.py"


rule rw05_table2:
    input:
        euler=rw05_runs("timestep", [f"euler_K={K}" for K in TS["steps"]], TS["ensembles"], TS["particles"]),
        strang=rw05_runs("timestep", [f"strang_K={K}" for K in TS["steps"]], TS["ensembles"], TS["particles"]),
    output:
        csv=report("results/tables/rw05_table2.csv", caption=item_caption("rw05_table2"), category="RW05"),
    log:
        "logs/tables/rw05_table2.log",
    benchmark:
        "benchmarks/tables/rw05_table2.tsv"
    params:
        dt_unit=RW05["dt_unit"],
    script:
        "../scripts/rw05_timestep_table.py"


report_item("RW05", "Table 1", rules.rw05_table1, "table", rules.rw05_table1.output.csv,
            "no-splitting on [0, 8]: E_end, Conf_end, E_max against eq. (28); errors O(1/n) (CF ≈ 4), Conf_end O(1/√n) (CF ≈ 2)",
            runs=rules.rw05_table1.input.runs, run_rule=rules.rw05_run, compare="rw05_table1", published="rw05_table1")
report_item("RW05", "Table 2", rules.rw05_table2, "table", rules.rw05_table2.output.csv,
            "n = 4096: E_max of Euler (first order, CF ≈ 2) and Strang splitting (second order, CF ≈ 4) for K = 4 … 32",
            runs=rules.rw05_table2.input, run_rule=rules.rw05_run, compare="rw05_table2", published="rw05_table2")


# ----------------------------------------------------------------------------- Figs. 1, 2
for _fig, _what in (("1", "no-splitting: confidence bands against eq. (28) on [0, 8], n = 64 (left), 256 (right)"),
                    ("2", "zoom on [5, 8], n = 4096 (left), 65536 (right): eq. (28) mostly, then completely, inside the band")):

    rule:
        name:
            f"rw05_fig{_fig}"
        input:
            runs=rw05_runs("transient", "nosplit", TR["ensembles"], RW05[f"fig{_fig}"]["particles"]),
        output:
            png=report(f"figures/rw05_fig{_fig}.png", caption=item_caption(f"rw05_fig{_fig}"), category="RW05"),
            pdf=f"figures/rw05_fig{_fig}.pdf",
            summary=f"results/figures/rw05_fig{_fig}.json",
        log:
            f"logs/figures/rw05_fig{_fig}.log",
        benchmark:
            f"benchmarks/figures/rw05_fig{_fig}.tsv"
        params:
            t_range=RW05[f"fig{_fig}"]["t_range"],
        script:
            "../scripts/temperature_bands.py"

    _rule = getattr(rules, f"rw05_fig{_fig}")
    report_item("RW05", f"Fig. {_fig}", _rule, "figure", _rule.output.png, _what, runs=_rule.input.runs,
                run_rule=rules.rw05_run, summary=_rule.output.summary)


# ----------------------------------------------------------------------------- Figs. 3, 4
rule rw05_fig3:
    input:
        runs=expand(rules.rw05_run.output.h5, zip, exp=["crit"] * len(RW05["crit"]["particles"]),
                    scheme=["nosplit"] * len(RW05["crit"]["particles"]), N=RW05["crit"]["ensembles"],
                    n=RW05["crit"]["particles"]),
    output:
        png=report("figures/rw05_fig3.png", caption=item_caption("rw05_fig3"), category="RW05"),
        pdf="figures/rw05_fig3.pdf",
        summary="results/figures/rw05_fig3.json",
    log:
        "logs/figures/rw05_fig3.log",
    benchmark:
        "benchmarks/figures/rw05_fig3.tsv"
    params:
        label="n",
        exact=True,
    script:
        "../scripts/crit_curves.py"


rule rw05_moments:
    input:
        runs=rules.rw05_fig3.input.runs,
    output:
        png=report("figures/rw05_moments.png", caption=item_caption("rw05_moments"), category="RW05"),
        pdf="figures/rw05_moments.pdf",
        summary="results/figures/rw05_moments.json",
        csv="results/tables/rw05_moments.csv",
    log:
        "logs/figures/rw05_moments.log",
    benchmark:
        "benchmarks/figures/rw05_moments.tsv"
    params:
        times=[1, 2, 3, 4, 5, 6, 7, 8],  # the rows of the table (Crit(t) of tails.md)
    script:
        "../scripts/rw05_moments.py"


rule rw05_fig4:
    input:
        runs=rw05_runs("crit_schemes", ["nosplit", f"strang_K={CS['steps']}", f"euler_K={CS['steps']}"],
                       CS["ensembles"], CS["particles"]),
    output:
        png=report("figures/rw05_fig4.png", caption=item_caption("rw05_fig4"), category="RW05"),
        pdf="figures/rw05_fig4.pdf",
        summary="results/figures/rw05_fig4.json",
    log:
        "logs/figures/rw05_fig4.log",
    benchmark:
        "benchmarks/figures/rw05_fig4.tsv"
    params:
        label="scheme",
    script:
        "../scripts/crit_curves.py"


report_item("RW05", "Fig. 3", rules.rw05_fig3, "figure", rules.rw05_fig3.output.png,
            "no-splitting Crit(t) (eq. 29) for n = 256, 1024, 4096 (from below), N = 65536, 16384, 4096: grows from 0 to a positive steady value",
            runs=rules.rw05_fig3.input.runs, run_rule=rules.rw05_run, summary=rules.rw05_fig3.output.summary)
report_item("RW05", "moments", rules.rw05_moments, "figure", rules.rw05_moments.output.png,
            "(not in the paper) ⟨|v − V|⁴⟩(t) and Crit(t) of the Fig. 3 runs against the exact curves of "
            "the moment hierarchy (λ = 0), exact Crit(∞) = 0.11907",
            runs=rules.rw05_moments.input.runs, run_rule=rules.rw05_run, summary=rules.rw05_moments.output.summary,
            extra=[rules.rw05_moments.output.csv])
report_item("RW05", "Fig. 4", rules.rw05_fig4, "figure", rules.rw05_fig4.output.png,
            "Crit(t) for K = 32, n = N = 4096: no-splitting (thick), Strang (upper thin) ≈ no-splitting, Euler (lower thin) off",
            runs=rules.rw05_fig4.input.runs, run_rule=rules.rw05_run, summary=rules.rw05_fig4.output.summary)


# ----------------------------------------------------------------------------- Tables 3-6
_RS = RW05["steady"]
REPLICA_RUNS = {
    scheme: [_steady(scheme, exp=f"replica_{i}")[0] for i in range(1, _RS["replicas"] + 1)]
    for scheme in ("nosplit", f"euler_K={_RS['replica_euler_steps']}")
}


rule rw05_steady_replicas:
    input:
        nosplit=REPLICA_RUNS["nosplit"],
        euler=REPLICA_RUNS[f"euler_K={_RS['replica_euler_steps']}"],
    output:
        csv=report("results/tables/rw05_steady_replicas.csv", caption=item_caption("rw05_steady_replicas"), category="RW05"),
    log:
        "logs/tables/rw05_steady_replicas.log",
    benchmark:
        "benchmarks/tables/rw05_steady_replicas.tsv"
    params:
        dt_unit=RW05["dt_unit"],
    script:
        "../scripts/steady_replicas.py"


for _name, _layout, _runs, _what in (
    ("table3_euler", "steps", _steady("euler", RW05["steady"]["euler_steps"]),
     "Euler splitting, n = 65536: T∞, Error = |T∞ − 8/3| of first order in dt (CF ≈ 2), Conf, CPU ∝ K"),
    ("table4_strang", "steps", _steady("strang", RW05["steady"]["strang_steps"]),
     "Strang splitting, n = 65536: Error of second order (CF ≈ 4), CPU ≈ no-splitting at K = 32"),
    ("table5_nosplit", "single", _steady("nosplit"), "no-splitting, n = 65536: no time-step error (CPU = 1)"),
    ("table6", "methods", _steady(["euler_K={}".format(RW05["hot"]["steps"]), "strang_K={}".format(RW05["hot"]["steps"]),
                                   "nosplit"], exp="hot"),
     "β = 37.5 (T∞ = 100), K = 32: Euler 9.6 % off, Strang 0.26 %, no-splitting 0.02 %"),
):

    rule:
        name:
            f"rw05_{_name}"
        input:
            runs=_runs,
            nosplit=_runs[-1:] if _layout == "methods" else _steady("nosplit"),
        output:
            csv=report(f"results/tables/rw05_{_name}.csv", caption=item_caption(f"rw05_{_name}"), category="RW05"),
        log:
            f"logs/tables/rw05_{_name}.log",
        benchmark:
            f"benchmarks/tables/rw05_{_name}.tsv"
        params:
            layout=_layout,
            dt_unit=RW05["dt_unit"],
        script:
            "../scripts/steady_table.py"

    _rule = getattr(rules, f"rw05_{_name}")
    report_item("RW05", f"Table {_name[5]}", _rule, "table", _rule.output.csv, _what, runs=_rule.input.runs,
                run_rule=rules.rw05_run, compare="steady", published=f"rw05_{_name}",
                extra=[rules.rw05_steady_replicas.output.csv])


rule rw05_effort:
    input:
        runs=_steady("nosplit") + _steady("euler", RW05["steady"]["euler_steps"])
        + _steady("strang", RW05["steady"]["strang_steps"]),
    output:
        csv=report("results/tables/rw05_effort.csv", caption=item_caption("rw05_effort"), category="RW05"),
    log:
        "logs/tables/rw05_effort.log",
    benchmark:
        "benchmarks/tables/rw05_effort.tsv"
    params:
        dt_unit=RW05["dt_unit"],
        steady_from=RW05["steady"]["steady_from"],
    script:
        "../scripts/rw05_effort.py"


report_item("RW05", "Effort model (§4.2)", rules.rw05_effort, "table", rules.rw05_effort.output.csv,
            "N_coll = 2(n−1)s_M; N_kick = 2N_coll + nM (no-splitting), s_M n/Δt (splitting): equal effort at Δt ≈ 1/4 (K ≈ 32)",
            runs=rules.rw05_effort.input.runs, run_rule=rules.rw05_run, compare="effort")


report_item("RW05", "Steady-state repeats (our check of Conf)", rules.rw05_steady_replicas, "table",
            rules.rw05_steady_replicas.output.csv,
            "Tables 3-6 take the M = 64 observations of one run as independent ('big enough to assure almost "
            "independent observations'); repeated runs with other seeds measure the real spread of T∞",
            runs=rules.rw05_steady_replicas.input, run_rule=rules.rw05_run, compare="replicas")
