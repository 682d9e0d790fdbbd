import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.theory.shear")  # alias for a release
