import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.reproduction.rheology")  # alias for a release
