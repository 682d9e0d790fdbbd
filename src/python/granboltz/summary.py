import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.output.summary")  # alias for a release
