import importlib, sys; sys.modules[__name__] = importlib.import_module("granboltz.reproduction.disks")  # alias for a release
