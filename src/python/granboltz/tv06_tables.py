import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.reproduction.tv06_tables")  # alias for a release
