"""granboltz: read, analyse and plot the outputs of the granboltz simulator, and run it.

    import granboltz
    run = granboltz.read_run("out.h5")        # granboltz.output.run.read_run
    run.time, run.temperature.mean, run.temperature.ci
    granboltz.simulate(config)                # granboltz.lib.inprocess.simulate

Sub-packages, one layer each; a layer imports only the layers above it in this list (checked by
tests/check_layers_python.py), and nothing heavy is imported until it is used:
    theory        closed forms and exact results, pure (no files, no verdicts); LAMBDA_P
    output        reading outputs: read_run, RunReadError, the HDF5 layout, plotting, files
    analysis      estimators on arrays and runs: finite size, tail exponents, moment checks
    lib           the simulator in this process (extension granboltz._core): simulate,
                  Simulation, ConfigError, SimulationBusyError
    study         parameter studies: Study, python -m granboltz.study run|table STUDY.yaml
    reproduction  the papers' tables and "Beyond the papers": table rows and verdicts
    report        the reproduction report (Markdown, HTML, LaTeX)
Modules still at the top level: transport, transport_table, relaxation, rheology, shear (the
transport coefficients and the shear flow). The old module paths (granboltz.run, .io, .dsmc,
.study_table, .sonine, ...) are one-line aliases of their new places, kept for a release.

On the package itself: read_run, RunReadError, Study, simulate, Simulation, ConfigError,
SimulationBusyError, __version__.
"""

__version__ = "0.1.0"


def __getattr__(name):
    # read_run, RunReadError and Study on the package itself, imported on first use (h5py, yaml;
    # pandas for Study.table).
    if name == "read_run":
        from .output.run import read_run

        return read_run
    if name == "Study":
        from .study.table import Study

        return Study
    if name == "RunReadError":
        from .output.io import RunReadError

        return RunReadError
    if name in ("simulate", "Simulation", "ConfigError", "SimulationBusyError"):
        # The compiled extension granboltz._core, loaded on first use (module granboltz.lib.inprocess).
        import importlib

        return getattr(importlib.import_module(".lib.inprocess", __name__), name)
    raise AttributeError(f"module 'granboltz' has no attribute {name!r}")
