import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.output.frames")  # alias for a release
