"""TV06: Talbot, Viot, Application of the Gillespie algorithm to a granular intruder particle,
arXiv:cond-mat/0608158.

Raw runs:  results/tv06/<experiment>/M=<M>/alpha=<alpha>/N=<ensembles>/collisions=<collisions>/run.h5
           with <experiment> = fig3 (Gaussian bath), fig4 (power-law bath, with v1 histograms),
           fig7, fig8 (needle), sec4_gillespie, sec4_dsmc (§4); the simulator's models intruder
           and needle (docs/tv06.md)
Items:     Figs. 1, 2 (analytic), Fig. 3 (eq. 18), Figs. 4, 5 (power-law bath), Fig. 7 and the
           temperatures of §3.2 (needle), Fig. 8, and §4 (DSMC against Gillespie).
"""

TV06 = config["tv06"]
TV06_STEP_MEM_MB = 2000  # memory declared by a figure or table step (numpy, matplotlib, histograms)
# experiment -> (simulator model, config block, bath kind, intruder method)
TV06_EXPERIMENTS = {
    "fig3": ("intruder", "fig3", "gaussian", "gillespie"),
    "fig4": ("intruder", "fig4", "powerlaw", "gillespie"),
    "fig7": ("needle", "fig7", None, None),
    "fig8": ("needle", "fig8", None, None),
    "sec4_gillespie": ("intruder", "sec4", "gaussian", "gillespie"),
    "sec4_dsmc": ("intruder", "sec4", "gaussian", "dsmc"),
}


def tv06_check_config(tv):
    """Cross-key checks of the tv06 block the schema cannot express (ValueError naming the key)."""
    if tv["fig5"]["mass"] not in tv["fig4"]["masses"]:
        raise ValueError("tv06.fig5.mass: must be one of tv06.fig4.masses")
    h = tv["fig4"]["histogram"]
    ratio = tv["fig5"]["bin_width"] / (2 * h["range"] / h["bins"])
    if abs(ratio - round(ratio)) > 1e-9 * ratio or round(ratio) < 1:
        raise ValueError("tv06.fig5.bin_width: must be a whole multiple of the fig4 histogram bin width")
    if not tv["fig5"]["tail_from"] < tv["fig5"]["tail_window"][0] < tv["fig5"]["tail_window"][1] <= h["range"]:
        raise ValueError("tv06.fig5: need tail_from < tail_window[0] < tail_window[1] <= fig4.histogram.range")
    for name, key in (("fig1", "v1_range"), ("fig2", "v_range")):
        if not tv[name][key][0] < tv[name][key][1]:
            raise ValueError(f"tv06.{name}.{key}: need lower < upper")


tv06_check_config(TV06)


def tv06_fmt(x):
    """A number as it appears in a run path: 0.5, 1, 0.1 (Python's %g)."""
    return f"{float(x):g}"


def tv06_runs(experiment, masses=None, alphas=None):
    """The HDF5 outputs of an experiment for every M in masses and alpha in alphas (default: the
    experiment's own lists; fig3 and fig8 have one mass)."""
    e = TV06[TV06_EXPERIMENTS[experiment][1]]
    masses = masses if masses is not None else e.get("masses", [e.get("mass")])
    alphas = alphas if alphas is not None else e.get("alphas", [e.get("alpha")])
    return expand(rules.tv06_run.output.h5, experiment=experiment, M=[tv06_fmt(m) for m in masses],
                  alpha=[tv06_fmt(a) for a in alphas], N=e["ensembles"], collisions=e["collisions"])


def tv06_run_config(wildcards):
    """Run config of results/tv06/{experiment}/M={M}/alpha={alpha}/N={N}/collisions={collisions}:
    model intruder (bath, method, histogram, DSMC bath keys) or needle (length, a, histogram)."""
    model, block, bath, method = TV06_EXPERIMENTS[wildcards.experiment]
    e = TV06[block]
    body = {"mass": float(wildcards.M), "alpha": float(wildcards.alpha), "density": TV06["density"],
            "collisions": int(wildcards.collisions)}
    if model == "needle":
        body.update(length=TV06["needle"]["length"], a=TV06["needle"]["a"])
        if "omega_histogram" in e:
            body["omega_histogram"] = dict(e["omega_histogram"])
    else:
        body = {"bath": {"kind": bath, "a": e["bath_a"]}, **body, "method": method}
        if "histogram" in e:
            body["histogram"] = dict(e["histogram"])
        if method == "dsmc":
            body.update(bath_particles=e["bath_particles"], bath_refresh=e["bath_refresh"])
    label = f"tv06/{wildcards.experiment}/M={wildcards.M}/alpha={wildcards.alpha}"
    return {"model": model, "seed": run_seed(label), "ensembles": int(wildcards.N), model: body}


TV06_WILDCARDS = dict(experiment="|".join(TV06_EXPERIMENTS), M="[0-9.e+-]+", alpha="[0-9.e+-]+", N="[0-9]+",
                      collisions="[0-9]+")


localrules:
    tv06_run_config,


use rule run_config as tv06_run_config with:
    output:
        yaml="results/tv06/{experiment}/M={M}/alpha={alpha}/N={N}/collisions={collisions}/run.yaml",
    log:
        "logs/tv06/{experiment}/M={M}/alpha={alpha}/N={N}/collisions={collisions}/run_config.log",
    params:
        run=tv06_run_config,
    wildcard_constraints:
        **TV06_WILDCARDS,


use rule run as tv06_run with:
    input:
        config=rules.tv06_run_config.output.yaml,
        granboltz=config["granboltz"],
    output:
        h5="results/tv06/{experiment}/M={M}/alpha={alpha}/N={N}/collisions={collisions}/run.h5",
    log:
        "logs/tv06/{experiment}/M={M}/alpha={alpha}/N={N}/collisions={collisions}/run.log",
    benchmark:
        "benchmarks/tv06/{experiment}/M={M}/alpha={alpha}/N={N}/collisions={collisions}/run.tsv"
    wildcard_constraints:
        **TV06_WILDCARDS,
    resources:
        mem_mb=config["run_mem_mb"],


def tv06_outputs(name, csv=True):
    """The outputs of a figure step: png (in the report), pdf, the numbers (csv), the summary."""
    out = {"png": report(f"figures/tv06_{name}.png", caption=item_caption(f"tv06_{name}"), category="TV06"),
           "pdf": f"figures/tv06_{name}.pdf", "summary": f"results/figures/tv06_{name}.json"}
    if csv:
        out["csv"] = f"results/tables/tv06_{name}.csv"
    return out


# ----------------------------------------------------------------------------- Figs. 1, 2 (analytic)
rule tv06_fig1:
    output:
        **tv06_outputs("fig1"),
    log:
        "logs/figures/tv06_fig1.log",
    benchmark:
        "benchmarks/figures/tv06_fig1.tsv"
    params:
        a=TV06["fig1"]["a"],
        rho=TV06["density"],
        v1_range=TV06["fig1"]["v1_range"],
        table_step=TV06["fig1"]["table_step"],
    threads: 1
    resources:
        mem_mb=TV06_STEP_MEM_MB,
    script:
        "../scripts/tv06_collision_rates.py"


rule tv06_fig2:
    output:
        **tv06_outputs("fig2"),
    log:
        "logs/figures/tv06_fig2.log",
    benchmark:
        "benchmarks/figures/tv06_fig2.tsv"
    params:
        a=TV06["fig2"]["a"],
        rho=TV06["density"],
        v1=TV06["fig2"]["v1"],
        v_range=TV06["fig2"]["v_range"],
        table_step=TV06["fig2"]["table_step"],
    threads: 1
    resources:
        mem_mb=TV06_STEP_MEM_MB,
    script:
        "../scripts/tv06_colliding_velocity.py"


report_item("TV06", "Fig. 1", rules.tv06_fig1, "figure", rules.tv06_fig1.output.png,
            "collision rates φ±(v1) and φ(v1) = φ+ + φ− of a surface moving at v1 in a Gaussian bath, eqs. (15)–(16), "
            "a = 0.5, 1, 2, 4 top to bottom", summary=rules.tv06_fig1.output.summary)
report_item("TV06", "Fig. 2", rules.tv06_fig2, "figure", rules.tv06_fig2.output.png,
            "density g+(v, v1) of the velocity of the bath particles hitting the right-hand side, eq. (12), "
            "Gaussian bath, v1 = −2, −1, 0, 1, 2 left to right", summary=rules.tv06_fig2.output.summary)


# ----------------------------------------------------------------------------- Fig. 3
rule tv06_fig3:
    input:
        runs=tv06_runs("fig3"),
    output:
        **tv06_outputs("fig3"),
    log:
        "logs/figures/tv06_fig3.log",
    benchmark:
        "benchmarks/figures/tv06_fig3.tsv"
    threads: 1
    resources:
        mem_mb=TV06_STEP_MEM_MB,
    script:
        "../scripts/tv06_temperature_ratio.py"


report_item("TV06", "Fig. 3", rules.tv06_fig3, "figure", rules.tv06_fig3.output.png,
            "T/T_B of the intruder (M = m, Gaussian bath, 500 000 collisions) against α: symbols on the exact "
            "curve (1 + α)/(2 + (1 − α)/M) of Martin and Piasecki, eq. (18)", runs=rules.tv06_fig3.input.runs,
            run_rule=rules.tv06_run, summary=rules.tv06_fig3.output.summary)
report_item("TV06", "Fig. 3 data", rules.tv06_fig3, "table", rules.tv06_fig3.output.csv,
            "the points of Fig. 3 (no numbers printed)", runs=rules.tv06_fig3.input.runs, run_rule=rules.tv06_run,
            compare="tv06_temperature")


# ----------------------------------------------------------------------------- Figs. 4, 5
rule tv06_fig4:
    input:
        runs=tv06_runs("fig4"),
    output:
        **tv06_outputs("fig4"),
    log:
        "logs/figures/tv06_fig4.log",
    benchmark:
        "benchmarks/figures/tv06_fig4.tsv"
    threads: 1
    resources:
        mem_mb=TV06_STEP_MEM_MB,
    script:
        "../scripts/tv06_powerlaw_temperature.py"


rule tv06_fig5:
    input:
        runs=tv06_runs("fig4", masses=[TV06["fig5"]["mass"]]),
    output:
        **tv06_outputs("fig5"),
    log:
        "logs/figures/tv06_fig5.log",
    benchmark:
        "benchmarks/figures/tv06_fig5.tsv"
    params:
        **TV06["fig5"],
    threads: 1
    resources:
        mem_mb=TV06_STEP_MEM_MB,
    script:
        "../scripts/tv06_powerlaw_distribution.py"


report_item("TV06", "Fig. 4", rules.tv06_fig4, "figure", rules.tv06_fig4.output.png,
            "T/T_B against α in the power-law bath, eq. (19), M = 1 and 0.5 (top to bottom), with the Gaussian-bath "
            "curves of eq. (18) dashed; close to them for α > M; exact T/T_B = α at M = α",
            runs=rules.tv06_fig4.input.runs, run_rule=rules.tv06_run, summary=rules.tv06_fig4.output.summary)
report_item("TV06", "Fig. 4 data", rules.tv06_fig4, "table", rules.tv06_fig4.output.csv,
            "the points of Fig. 4 (no numbers printed)", runs=rules.tv06_fig4.input.runs, run_rule=rules.tv06_run,
            compare="tv06_temperature")
report_item("TV06", "Fig. 5", rules.tv06_fig5, "figure", rules.tv06_fig5.output.png,
            "intruder velocity distributions, power-law bath, M = 1/2, α = 0, 0.1, …, 1 (top to bottom); inset: "
            "log–log, tails ∝ v^−4 for every α; exact at α = M = 1/2: the bath's own form, eq. (19)",
            runs=rules.tv06_fig5.input.runs, run_rule=rules.tv06_run, summary=rules.tv06_fig5.output.summary)


# ----------------------------------------------------------------------------- Figs. 7, 8 (needle)
rule tv06_fig7:
    input:
        runs=tv06_runs("fig7"),
    output:
        **tv06_outputs("fig7"),
    log:
        "logs/figures/tv06_fig7.log",
    benchmark:
        "benchmarks/figures/tv06_fig7.tsv"
    threads: 1
    resources:
        mem_mb=TV06_STEP_MEM_MB,
    script:
        "../scripts/tv06_needle_correlation.py"


rule tv06_fig8:
    input:
        runs=tv06_runs("fig8"),
    output:
        **tv06_outputs("fig8"),
    log:
        "logs/figures/tv06_fig8.log",
    benchmark:
        "benchmarks/figures/tv06_fig8.tsv"
    threads: 1
    resources:
        mem_mb=TV06_STEP_MEM_MB,
    script:
        "../scripts/tv06_needle_omega.py"


report_item("TV06", "Fig. 7", rules.tv06_fig7, "figure", rules.tv06_fig7.output.png,
            "needle (L = 1, Gaussian bath a = 1): R = ⟨v²ω²⟩/(⟨v²⟩⟨ω²⟩), eq. (30), against α for M = 0.1, 0.5, 1 "
            "(top to bottom): R > 1, growing as α decreases and for light needles; R = 1 at α = 1",
            runs=rules.tv06_fig7.input.runs, run_rule=rules.tv06_run, summary=rules.tv06_fig7.output.summary)
report_item("TV06", "Fig. 7 and §3.2 data", rules.tv06_fig7, "table", rules.tv06_fig7.output.csv,
            "R of Fig. 7 and the temperatures of §3.2: T_B > T_translational > T_rotational for α < 1",
            runs=rules.tv06_fig7.input.runs, run_rule=rules.tv06_run, compare="tv06_needle")
report_item("TV06", "Fig. 8", rules.tv06_fig8, "figure", rules.tv06_fig8.output.png,
            "angular-velocity distribution of the needle, M = 0.1, α = 0.1, 5 000 000 collisions (black) and the "
            "best-fit Gaussian (red): deviations become apparent for a light needle and strong inelasticity",
            runs=rules.tv06_fig8.input.runs, run_rule=rules.tv06_run, summary=rules.tv06_fig8.output.summary)


# ----------------------------------------------------------------------------- §4
rule tv06_dsmc:
    input:
        gillespie=tv06_runs("sec4_gillespie"),
        dsmc=tv06_runs("sec4_dsmc"),
    output:
        csv=report("results/tables/tv06_dsmc.csv", caption=item_caption("tv06_dsmc"), category="TV06"),
    log:
        "logs/tables/tv06_dsmc.log",
    benchmark:
        "benchmarks/tables/tv06_dsmc.tsv"
    threads: 1
    resources:
        mem_mb=TV06_STEP_MEM_MB,
    script:
        "../scripts/tv06_dsmc_table.py"


report_item("TV06", "§4 DSMC and Gillespie", rules.tv06_dsmc, "table", rules.tv06_dsmc.output.csv,
            "the DSMC version of the 1-D intruder (§4) gives the same results as the Gillespie algorithm, with "
            "comparable effort (no numbers printed)", runs=rules.tv06_dsmc.input, run_rule=rules.tv06_run,
            compare="tv06_dsmc")


TV06_OUTPUTS = [item["output"] for item in REPORT_ITEMS if item["paper"] == "TV06"]
