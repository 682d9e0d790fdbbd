import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.study.table")  # alias for a release
