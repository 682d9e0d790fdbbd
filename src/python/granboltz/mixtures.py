import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.reproduction.mixtures")  # alias for a release
