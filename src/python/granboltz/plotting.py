import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.output.plotting")  # alias for a release
