import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.output.intervals")  # alias for a release
