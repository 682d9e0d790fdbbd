import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.analysis.local_exponent")  # alias for a release
