"""granboltz.lib: the simulator in this Python process (the compiled extension granboltz._core).

Modules:
    inprocess  simulate, Simulation, ConfigError, SimulationBusyError
    arguments  the checks of the arguments passed to the extension
    progress   the progress bar of simulate and the SIGINT pause
    cli        the `granboltz` command installed with the package (the simulator's path)

simulate, Simulation, ConfigError and SimulationBusyError are also this package's names (and the
package granboltz's), loaded on first use.
"""

_NAMES = ("simulate", "Simulation", "ConfigError", "SimulationBusyError")


def __getattr__(name):
    if name in _NAMES:
        import importlib

        return getattr(importlib.import_module(".inprocess", __name__), name)
    raise AttributeError(f"module 'granboltz.lib' has no attribute {name!r}")
