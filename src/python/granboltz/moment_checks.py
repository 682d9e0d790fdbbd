import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.analysis.moment_checks")  # alias for a release
