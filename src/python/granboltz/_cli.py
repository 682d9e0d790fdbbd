import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.lib.cli")  # alias for a release
