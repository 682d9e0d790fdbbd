import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.reproduction.rough")  # alias for a release
