import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.reproduction.tables")  # alias for a release
