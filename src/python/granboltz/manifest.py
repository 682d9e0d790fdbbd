import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.output.manifest")  # alias for a release
