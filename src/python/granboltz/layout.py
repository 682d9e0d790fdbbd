import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.output.layout")  # alias for a release
