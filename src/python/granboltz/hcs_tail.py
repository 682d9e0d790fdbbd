import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.reproduction.hcs_tail")  # alias for a release
