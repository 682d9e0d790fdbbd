import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.study.grid")  # alias for a release
