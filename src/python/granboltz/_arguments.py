import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.lib.arguments")  # alias for a release
