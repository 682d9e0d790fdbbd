import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.reproduction.viscoelastic")  # alias for a release
