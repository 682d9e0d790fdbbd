import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.analysis.finite_size")  # alias for a release
