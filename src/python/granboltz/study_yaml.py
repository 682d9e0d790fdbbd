import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.study.safe_yaml")  # alias for a release
