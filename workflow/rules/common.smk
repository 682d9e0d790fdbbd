"""Config validation and helpers shared by the rule files (the Snakefile includes this first)."""

import zlib

from snakemake.utils import validate


validate(config, schema="../schemas/config.schema.yaml")


def check_config(cfg):
    """Cross-key checks the schema cannot express; raise ValueError naming the offending key."""
    for paper in ("grw05",):
        for name, item in cfg[paper].items():
            if "observe_every" in item:  # a DSMC experiment
                steps = item["t_end"] / item["observe_every"]
                if abs(steps - round(steps)) > 1e-9 * steps:
                    raise ValueError(f"{paper}.{name}: t_end must be a whole multiple of observe_every")
    t_min, t_max = cfg["grw05"]["fig1"]["t_range"]
    if not t_min < t_max <= cfg["grw05"]["ex3"]["t_end"]:
        raise ValueError("grw05.fig1.t_range: need t_min < t_max <= grw05.ex3.t_end")


check_config(config)


wildcard_constraints:
    ex="ex[0-9]+",
    N="[0-9]+",
    n="[0-9]+",


def run_seed(label):
    """Seed of one run: the base seed plus crc32(label), label = "<paper>/<experiment>/n=<n>".

    The simulator keys its random streams by (seed, ensemble, consumer), so runs with different
    labels draw independent streams, a rerun is identical, and the first N ensembles of a run do
    not depend on how many ensembles it has.
    """
    return config["seed"] + zlib.crc32(label.encode())


def dsmc_run_config(paper, ex, N, n):
    """The simulator's run config (a dict, written as YAML) for experiment config[paper][ex]."""
    e = config[paper][ex]
    return {
        "model": "dsmc",
        "seed": run_seed(f"{paper}/{ex}/n={n}"),
        "ensembles": int(N),
        "dsmc": {
            "particles": int(n),
            "scheme": e["scheme"],
            "alpha": e["alpha"],
            "beta": e["beta"],
            "gamma": e["gamma"],
            "kernel": {"lambda": e["kernel"]["lambda"], "C": e["kernel"]["C"]},
            "initial": {"temperature": e["temperature0"]},
            "t_end": e["t_end"],
            "observe_every": e["observe_every"],
            "majorant_update": e["majorant_update"],
        },
    }
