import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.output.histograms")  # alias for a release
