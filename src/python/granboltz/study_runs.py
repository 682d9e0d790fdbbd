import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.study.runs")  # alias for a release
