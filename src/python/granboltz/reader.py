import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.output.reader")  # alias for a release
