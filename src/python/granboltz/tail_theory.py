import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.theory.tail_theory")  # alias for a release
