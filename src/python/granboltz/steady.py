import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.reproduction.steady")  # alias for a release
