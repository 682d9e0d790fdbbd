import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.lib.inprocess")  # alias for a release
