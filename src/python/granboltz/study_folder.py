import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.study.folder")  # alias for a release
