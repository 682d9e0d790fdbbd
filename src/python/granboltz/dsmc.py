import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.reproduction.dsmc")  # alias for a release
