import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.study.snakemake")  # alias for a release
