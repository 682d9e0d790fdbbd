# The Snakefile of granboltz parameter studies (granboltz.study): one rule, a point's config ->
# its run. granboltz.study calls it with --snakefile (this file, by absolute path), --directory
# (the study folder studies/<study>/, whatever the current directory) and --config
# granboltz=<the simulator>, with the runs to make as targets. Jobs through a profile
# (--profile workflow/profiles/slurm) run this same rule.

rule study_point:
    input:
        "points/{hash}.yaml",
    output:
        "runs/{hash}.h5",
    log:
        "logs/{hash}.log",
    wildcard_constraints:
        hash="[0-9a-f]{12}",
    params:
        granboltz=config["granboltz"],
    threads: 1
    # exec: no shell between Snakemake (or the SLURM job script) and the simulator
    shell:
        "exec {params.granboltz:q} run {input:q} -o {output:q} --threads {threads} > {log:q} 2>&1"
