import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.output.ratios")  # alias for a release
