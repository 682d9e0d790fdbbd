import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.output.species")  # alias for a release
