import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.reproduction.transport_table")  # alias for a release
