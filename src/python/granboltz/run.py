import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.output.run")  # alias for a release
