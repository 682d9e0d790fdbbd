import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.output.files")  # alias for a release
