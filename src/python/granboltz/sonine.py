import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.theory.sonine")  # alias for a release
