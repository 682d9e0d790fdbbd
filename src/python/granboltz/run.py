"""Reading any granboltz output (DSMC, TV06 intruder or needle) into one object: read_run(path).

    run = read_run("out.h5")
    run.time                         # observation times t_m (DSMC), NumPy array
    run.temperature.mean, .ci        # an observable: ensemble mean and its confidence half-width
    run.observables                  # {name: Observable} of every observable in the file
    run.histograms["histogram"]      # read from the file only when first asked for
    run.events["collisions"]         # per-ensemble counters
    run.config, run.provenance       # the resolved config; version, commit, threads, wall time, ...

A merged file (`granboltz merge`) is identical to the unsharded run and reads the same; a single
shard is read too, but its means cover only its ensembles: run.shard gives (index, count) and
run.complete is False for it. Every dataset read goes through granboltz.io.read_dataset, so a
corrupted dataset raises granboltz.io.RunReadError naming the file and the dataset.
"""

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from .io import open_run, provenance, read_config, read_dataset

_HISTOGRAM_GROUPS = ("histogram", "velocity_histogram", "omega_histogram")
_NOT_OBSERVABLES = {"events", "steady", "accumulators", "provenance", "exact"} | set(_HISTOGRAM_GROUPS)


@dataclass(frozen=True)
class Observable:
    """One observable over the ensembles: mean, confidence half-width ci (lambda_p = 3.2, GRW05
    eq. 31) and variance, each [M+1, ...] for DSMC series or scalars for TV06 time averages;
    per_ensemble [N] where the file has it (TV06), else None."""

    name: str
    mean: np.ndarray
    ci: np.ndarray
    variance: np.ndarray = None
    per_ensemble: np.ndarray = None

    @property
    def lower(self):
        """mean - ci: the lower end of the confidence band."""
        return self.mean - self.ci

    @property
    def upper(self):
        """mean + ci: the upper end of the confidence band."""
        return self.mean + self.ci


class LazyHistograms(Mapping):
    """The histograms of a run file by group name ({dataset name: array} each), read from the
    file on first access and then kept: large histograms cost nothing until they are used."""

    def __init__(self, path, names):
        self._path, self._names, self._cache = str(path), tuple(names), {}

    def __getitem__(self, name):
        if name not in self._names:
            raise KeyError(f"{self._path} has no histogram {name!r} (it has: {', '.join(self._names) or 'none'})")
        if name not in self._cache:
            with open_run(self._path) as f:
                group = f[name]
                self._cache[name] = {key: read_dataset(f, f"{name}/{key}", self._path)
                                     for key in group if not hasattr(group[key], "keys")}
        return self._cache[name]

    def __iter__(self):
        return iter(self._names)

    def __len__(self):
        return len(self._names)


@dataclass
class Run:
    """One granboltz output file, read by read_run. Observables are also attributes:
    run.temperature is run.observables["temperature"]."""

    path: str
    model: str
    config: dict
    ensembles: int
    time: np.ndarray
    observables: dict
    histograms: LazyHistograms
    events: dict
    steady: dict
    exact: dict
    provenance: dict

    def __getattr__(self, name):
        observables = self.__dict__.get("observables", {})
        if name in observables:
            return observables[name]
        raise AttributeError(f"{type(self).__name__} has no attribute or observable {name!r}")

    def __getitem__(self, name):
        """run["temperature"]: the observable of that name."""
        return self.observables[name]

    @property
    def shard(self):
        """(index, count) when the file is one shard of a larger run (provenance shard "i/count"
        with count > 1), None for a whole run or a merged one."""
        if "merged_from" in self.provenance:
            return None
        index, _, count = str(self.provenance.get("shard", "")).partition("/")
        if not count or int(count) <= 1:
            return None
        return int(index), int(count)

    @property
    def complete(self):
        """False for a single shard (its means cover only its ensembles; merge the shards with
        `granboltz merge`), True otherwise."""
        return self.shard is None


def _observable(f, name, path):
    group = f[name]
    return Observable(name=name, mean=read_dataset(f, f"{name}/mean", path), ci=read_dataset(f, f"{name}/ci", path),
                      variance=read_dataset(f, f"{name}/variance", path) if "variance" in group else None,
                      per_ensemble=read_dataset(f, f"{name}/per_ensemble", path) if "per_ensemble" in group else None)


def _is_observable(f, name):
    return name not in _NOT_OBSERVABLES and hasattr(f[name], "keys") and "mean" in f[name] and "ci" in f[name]


def read_run(path):
    """Read a granboltz HDF5 output (any model) into a Run: config, time, every observable with
    its ci, the events, the steady-state averages (DSMC with steady_from), exact values (TV06),
    provenance, and the histograms lazily. RunReadError names the file and the dataset when
    HDF5 cannot read one."""
    path = str(path)
    with open_run(path) as f:
        config = read_config(f, path)
        observables = {name: _observable(f, name, path) for name in f if _is_observable(f, name)}
        steady = {}
        if "steady" in f:
            steady = {name: _observable(f, f"steady/{name}", path) for name in f["steady"]
                      if "mean" in f["steady"][name]}
        exact = {name: read_dataset(f, f"exact/{name}", path) for name in f["exact"]} if "exact" in f else {}
        events = {name: read_dataset(f, f"events/{name}", path) for name in f["events"]} if "events" in f else {}
        return Run(path=path, model=str(config.get("model", f.attrs.get("model", ""))), config=config,
                   ensembles=int(f.attrs["ensembles"]),
                   time=read_dataset(f, "time", path) if "time" in f else None,
                   observables=observables,
                   histograms=LazyHistograms(path, [g for g in _HISTOGRAM_GROUPS if g in f]),
                   events=events, steady=steady, exact=exact, provenance=provenance(f))
