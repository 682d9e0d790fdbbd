import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.lib.progress")  # alias for a release
