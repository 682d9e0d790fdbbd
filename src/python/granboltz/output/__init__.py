"""granboltz.output: reading the simulator's outputs (imports only granboltz.theory and itself).

Modules:
    run         read_run: any output file as one object (observables with ci, lazy histograms)
    io          low-level HDF5 reading; RunReadError names the file and the dataset
    layout      the datasets and attributes every output of a model has, as read_run checks them
    reader      a file's datasets read once, checked against the layout
    intervals   the steady averages and their intervals
    ratios      correlated ratios of observables and their intervals
    histograms  the histograms of a run, read on first use
    species     a mixture's species
    manifest    the manifest of a sharded run
    summary     what repr(run) prints
    frames      a run's observables as pandas DataFrames, plotted
    plotting    matplotlib with the house style, reproducible figure files
    files       atomic CSV/text/JSON writing

read_run and RunReadError are also this package's names, imported on first use (h5py).
"""


def __getattr__(name):
    if name == "read_run":
        from .run import read_run

        return read_run
    if name == "RunReadError":
        from .io import RunReadError

        return RunReadError
    raise AttributeError(f"module 'granboltz.output' has no attribute {name!r}")
