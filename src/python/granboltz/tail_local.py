import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.analysis.tail_local")  # alias for a release
