import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.theory.dimension")  # alias for a release
