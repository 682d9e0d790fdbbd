import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.study.spec")  # alias for a release
