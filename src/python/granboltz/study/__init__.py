"""granboltz.study: parameter studies, a grid over a base config run through Snakemake.

    python -m granboltz.study run STUDY.yaml [--cores N]    # or table STUDY.yaml
    from granboltz.study import Study, run                   # the same from Python

Modules:
    command    prepare, run, main (the command line); its names are also this package's
    table      Study(folder): the points and their runs, Study.table() (pandas)
    spec       the study file: load_study, check_study, expand, point_hash, the point configs
    grid       the grid: full_grid, replicas and their seeds
    folder     the study folder: its lock, files written only when they change, damaged files
    runs       the runs of the points: check_runs, verify_runs
    snakemake  the Snakemake run with the package's Snakefile (study.smk)
    safe_yaml  YAML read with limits (size, nodes, depth); StudyError

Importing this package is light: the names of command (yaml) are loaded on first use.
"""

_SUBMODULES = {"command", "table", "spec", "grid", "folder", "runs", "snakemake", "safe_yaml"}


def __getattr__(name):
    # granboltz.study was one module before it became a package: its names stay reachable here.
    if name.startswith("__") or name in _SUBMODULES:
        raise AttributeError(name)
    import importlib

    try:
        return getattr(importlib.import_module(".command", __name__), name)
    except AttributeError:
        raise AttributeError(f"module 'granboltz.study' has no attribute {name!r}") from None
