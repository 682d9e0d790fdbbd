"""granboltz: read, analyse and plot the outputs of the granboltz simulator.

    import granboltz
    run = granboltz.read_run("out.h5")        # granboltz.run.read_run
    run.time, run.temperature.mean, run.temperature.ci

Modules, one concern each (import the one you need; nothing heavy is imported here):
    run          read_run: any output file as one object (observables with ci, lazy histograms)
    io           low-level HDF5 reading; RunReadError names the file and the dataset
    layout       the datasets and attributes every output of a model has, as read_run checks them
    dsmc         the DSMC runs of the GRW05/RW05 tables (temperature series, histogram, steady)
    theory       sub-package, the theory layer (pure; LAMBDA_P): closed_forms (temperature laws,
                 scheme values, the estimator's bias, TV06 §3.1), sonine (a2, a3, the steady
                 temperature), maxwell_hierarchy, tail_theory, dimension; the old paths
                 granboltz.sonine, .maxwell_hierarchy, .tail_theory, .dimension are aliases
    finite_size  fit_finite_size: T(n) = T_inf + c/n over runs at several n
    summary      what repr(run) prints
    tables       GRW05 Tables 1-2, RW05 Tables 1-2
    steady       RW05 Tables 3-6, repeated runs, the effort model
    tails        GRW05 §5.3 tail exponents
    tv06_tables, tv06_histograms   TV06 runs, tables and histograms
    beyond, viscoelastic, disks   the report section "Beyond the papers" (viscoelastic: free cooling,
                 T ~ t^(-5/3); disks: a2, a3 of hard disks in d = 2)
    mixtures     Garzó-Dufty partial cooling rates, T_i/T of the HCS and white noise, Martin-Piasecki
    rough        rough spheres: the Maxwellian theta = T_rot/T_tr of the HCS and white noise
    plotting     matplotlib with the house style, reproducible figure files
    files        atomic CSV/text/JSON writing
    study, study_table   parameter studies: a grid over a base config run through Snakemake
                 (python -m granboltz.study run STUDY.yaml); Study(folder).table(); their parts
                 study_yaml, study_spec, study_folder, study_runs, study_snakemake
    report       the reproduction report (subpackage)
    inprocess    the simulator in this process (extension granboltz._core): simulate, Simulation,
                 ConfigError, SimulationBusyError, also on the package itself
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
        # The compiled extension granboltz._core, loaded on first use (module granboltz.inprocess).
        import importlib

        return getattr(importlib.import_module(".inprocess", __name__), name)
    raise AttributeError(f"module 'granboltz' has no attribute {name!r}")
