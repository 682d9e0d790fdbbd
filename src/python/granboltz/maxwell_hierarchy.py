import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.theory.maxwell_hierarchy")  # alias for a release
