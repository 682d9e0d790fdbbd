import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.reproduction.beyond")  # alias for a release
