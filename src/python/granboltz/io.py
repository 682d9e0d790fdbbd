import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.output.io")  # alias for a release
