import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.analysis.tails")  # alias for a release
