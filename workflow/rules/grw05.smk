"""GRW05: Gamba, Rjasanow, Wagner, Math. Comput. Modelling 42 (2005) 683-700.

Raw runs:  results/grw05/<experiment>/N=<ensembles>/n=<particles>/run.h5
Items:     Table 1 and Fig. 1 (Example 3, §5.2).
"""


def grw05_runs(ex, particles):
    """The HDF5 outputs of experiment `ex` for each n in `particles` (N from the config)."""
    return expand(rules.grw05_run.output.h5, ex=ex, N=config["grw05"][ex]["ensembles"], n=particles)


localrules:
    grw05_run_config,


rule grw05_run_config:
    output:
        yaml="results/grw05/{ex}/N={N}/n={n}/run.yaml",
    log:
        "logs/grw05/{ex}/N={N}/n={n}/run_config.log",
    params:
        run=lambda wc: dsmc_run_config("grw05", wc.ex, wc.N, wc.n),
    script:
        "../scripts/write_run_config.py"


rule grw05_run:
    input:
        config=rules.grw05_run_config.output.yaml,
        granboltz=config["granboltz"],
    output:
        h5="results/grw05/{ex}/N={N}/n={n}/run.h5",
    log:
        "logs/grw05/{ex}/N={N}/n={n}/run.log",
    benchmark:
        "benchmarks/grw05/{ex}/N={N}/n={n}/run.tsv"
    threads: config["threads"]
    resources:
        mem_mb=config["run_mem_mb"],
    shell:
        "{input.granboltz} run {input.config} -o {output.h5} --threads {threads} > {log} 2>&1"


rule grw05_table1:
    input:
        runs=grw05_runs("ex3", config["grw05"]["ex3"]["particles"]),
    output:
        csv=report(
            "results/tables/grw05_table1.csv",
            caption="../report/grw05_table1.rst",
            category="GRW05",
        ),
    log:
        "logs/tables/grw05_table1.log",
    benchmark:
        "benchmarks/tables/grw05_table1.tsv"
    script:
        "../scripts/grw05_convergence_table.py"


rule grw05_fig1:
    input:
        runs=grw05_runs("ex3", config["grw05"]["fig1"]["particles"]),
    output:
        png=report("figures/grw05_fig1.png", caption="../report/grw05_fig1.rst", category="GRW05"),
        pdf="figures/grw05_fig1.pdf",
    log:
        "logs/figures/grw05_fig1.log",
    benchmark:
        "benchmarks/figures/grw05_fig1.tsv"
    params:
        t_range=config["grw05"]["fig1"]["t_range"],
    script:
        "../scripts/grw05_temperature_bands.py"
