import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.analysis.relaxation")  # alias for a release
