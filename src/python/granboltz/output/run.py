"""Reading any granboltz output (DSMC, TV06 intruder or needle) into one object: read_run(path).

    run = read_run("out.h5")
    run.time                         # observation times t_m (DSMC), NumPy array
    run.temperature.mean, .ci        # an observable: ensemble mean and its confidence half-width
    run.steady["temperature"].sigma  # a steady average: its standard error, .estimator, .tau_int, ...
    run.steady["temperature"].batch  # steady_ci: independent: the honest (batch) interval beside it
    run.observables                  # {name: Observable} of every observable in the file
    run.histograms["histogram"]      # read from the file only when first asked for
    run.events["collisions"]         # per-ensemble counters
    run.species["heavy"].temperature # a mixture's species (granboltz.output.species): observables, .a2, .steady,
                                     # .mass, .diameter, .fraction, .particles, .events
    run.temperature_rotational       # rough spheres: T_rot (run.temperature stays translational)
    run.theta, run.steady["theta"]   # rough spheres: theta = T_rot/T with its interval (granboltz.output.ratios)
    run.temperature_ratios["a_over_b"]  # mixtures: T_a/T_b per row; steady: run.steady["temperature_ratio/a_over_b"]
    run.config, run.provenance       # the resolved config; version, commit, threads, wall time, ...
    run.manifest["/temperature/mean"]  # DSMC: each dataset's shape, meaning, observer (None: older files)
    run.to_xarray(), run.to_dataframe(), run.plot("temperature", theory=...)  # granboltz.output.frames

A merged file (`granboltz merge`) is identical to the unsharded run and reads the same; a single
shard is read too, but its means cover only its ensembles: run.shard gives (index, count) and
run.complete is False for it.

read_run raises granboltz.output.io.RunReadError, naming the file and the dataset or attribute, for
anything that is not a complete output it can read: a file HDF5 cannot open or read (not HDF5,
truncated, a checksum failure), a checkpoint, an HDF5 file of another program, and a dataset or
attribute that every output of the file's model (and config) has but this file lacks, or has with
the wrong shape, dtype or non-finite values; with a /manifest (DSMC outputs of newer simulators),
a dataset it lists that is missing or has another shape, or a damaged manifest. The layout
checked is what the simulator writes (app/output.cpp, dsmc/run.cpp, tv06/run.cpp; docs/output.md). A
shard must have all of it too, for its own ensembles.
"""

from dataclasses import dataclass, field, replace

import h5py
import numpy as np

from . import frames
from .io import RunReadError, open_run, provenance, read_config, read_dataset, reading
from .intervals import Interval, read_fields, read_steady
from .histograms import LazyHistograms
from .layout import F8, U8, Spec, check_provenance, config_section, dsmc_layout, shard_range, tv06_layout
from .manifest import read_manifest
from .reader import Reader
from .species import read_species

_HISTOGRAM_GROUPS = ("histogram", "histogram_component", "velocity_histogram", "omega_histogram")
_NOT_OBSERVABLES = {"events", "steady", "accumulators", "provenance", "exact", "species", "manifest"} | set(_HISTOGRAM_GROUPS)


@dataclass(frozen=True)
class Observable:
    """One observable over the ensembles: mean, confidence half-width ci (lambda_p = 3.2, GRW05
    eq. 31) and variance, each [M+1, ...] for DSMC series or scalars for TV06 time averages;
    per_ensemble [N] where the file has it (TV06), else None.

    A steady average (run.steady) also has sigma, its standard error, with estimator, tau_int,
    effective_samples, block_rows (as Interval), and with steady_ci: independent batch, the
    Interval of the batch estimator of the same run (ci takes the correlated rows as independent,
    batch.ci does not). None where the file has none: series, TV06, older files. bias: the
    estimated bias of a ratio (a species' a2, a3), else None."""

    name: str
    mean: np.ndarray
    ci: np.ndarray
    variance: np.ndarray = None
    per_ensemble: np.ndarray = None
    sigma: np.ndarray = None
    estimator: str = None
    tau_int: float = None
    effective_samples: float = None
    block_rows: int = None
    batch: Interval = None
    bias: np.ndarray = None

    def __repr__(self):
        from .summary import observable_summary

        return observable_summary(self)

    @property
    def lower(self):
        """mean - ci: the lower end of the confidence band."""
        return self.mean - self.ci

    @property
    def upper(self):
        """mean + ci: the upper end of the confidence band."""
        return self.mean + self.ci


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
    species: dict = field(default_factory=dict)  # {name: granboltz.output.species.Species} of a mixture
    manifest: dict = None  # {path: granboltz.output.manifest.ManifestEntry}; None: TV06, or written before it

    def __getattr__(self, name):
        observables = self.__dict__.get("observables", {})
        if name in observables:
            return observables[name]
        raise AttributeError(f"{type(self).__name__} has no attribute or observable {name!r}")

    def __getitem__(self, name):
        """run["temperature"]: the observable of that name."""
        return self.observables[name]

    to_xarray, to_dataframe, plot = frames.to_xarray, frames.to_dataframe, frames.plot  # the run as data

    def __repr__(self):
        """A few lines: model, sizes, shard, time grid, observables, steady (or final) values."""
        from .summary import summarize

        return summarize(self)

    @property
    def temperature_ratios(self):
        """{"<a>_over_<b>": Observable} of a mixture: T_a/T_b per row for every pair a < b of its
        species (granboltz.output.ratios); the steady ones are run.steady["temperature_ratio/<a>_over_<b>"].
        {} for a one-species run and for files of simulators that did not store them.  (TV06's
        intruder has an observable temperature_ratio of its own: run.temperature_ratio.)"""
        head = "temperature_ratio/"
        return {k[len(head):]: v for k, v in self.__dict__.get("observables", {}).items() if k.startswith(head)}

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
    def dimension(self):
        """d of a DSMC run (dsmc.dimension: 3 unless the config says 2); None for TV06 runs.
        In d = 2 every vector and tensor keeps its 3-D shape with zero z entries."""
        if self.model != "dsmc":
            return None
        return int(self.config.get("dsmc", {}).get("dimension", 3))

    @property
    def complete(self):
        """False for a single shard (its means cover only its ensembles; merge the shards with
        `granboltz merge`), True otherwise."""
        return self.shard is None


def _read_observable(reader, name, specs):
    return Observable(name=name, **read_fields(reader, specs))  # mean, ci, variance[, per_ensemble]


def _read_other_observable(reader, name):
    """An observable group the layout does not name (a newer simulator's): read as it is."""
    f, path = reader.f, reader.path
    with reading(path, f"group /{name}"):
        group = f[name]
        members = set(group)
    return Observable(name=name, mean=read_dataset(f, f"{name}/mean", path),
                      ci=read_dataset(f, f"{name}/ci", path),
                      variance=read_dataset(f, f"{name}/variance", path) if "variance" in members else None,
                      per_ensemble=(read_dataset(f, f"{name}/per_ensemble", path)
                                    if "per_ensemble" in members else None),
                      sigma=read_dataset(f, f"{name}/sigma", path) if "sigma" in members else None)


def _has_mean_and_ci(reader, name):
    with reading(reader.path, f"group /{name}"):
        obj = reader.f.get(name)
        return isinstance(obj, h5py.Group) and "mean" in obj and "ci" in obj


def read_run(path):
    """Read a granboltz HDF5 output (any model) into a Run: config, time, every observable with
    its ci, the events, the steady-state averages (DSMC with steady_from), exact values (TV06),
    provenance, and the histograms lazily.

    Raises RunReadError, naming the file and the dataset or attribute, for anything that is not
    an output it can read: a missing path or a directory, a file HDF5 cannot open or read (not
    HDF5, truncated, a checksum failure), a checkpoint, an HDF5 file of another program (no
    config attribute), a config that is not YAML or has no model, and a dataset or attribute
    that every output of the model has but is missing, of the wrong shape or dtype, or not
    finite. A shard reads (run.complete is False) and must have every dataset too."""
    path = str(path)
    with open_run(path) as f:
        config = read_config(f, path)
        model = config["model"]
        reader = Reader(f, path, model)
        with reading(path, "the file"):
            return _read(reader, config, model)


def _read(reader, config, model):
    # The ensembles and the time grid come first: the layout's shapes depend on them.
    f, path, why = reader.f, reader.path, reader.why
    section = config_section(config, path, model)
    ensembles = reader.integer("/", "ensembles", why(), minimum=1)
    if config.get("ensembles") != ensembles:
        reader.fail("attribute ensembles", f"is {ensembles}, but the config says {config.get('ensembles')!r}")
    time = None
    if model == "dsmc":
        time = reader.dataset(Spec("time", F8, None, True, why()))
        if time.ndim != 1 or time.size == 0:
            reader.fail("dataset /time", f"has shape {time.shape}, not [M+1]")
        if np.any(np.diff(time) <= 0):
            reader.fail("dataset /time", "is not increasing")
    reader.group("provenance", why())
    prov = provenance(f, path)
    check_provenance(path, prov)
    first, last = shard_range(path, prov, ensembles)
    n = last - first
    reader.group("events", why())
    index = reader.dataset(Spec("events/ensemble", U8, (n,), True, why()))
    if not np.array_equal(index, np.arange(first, last)):
        reader.fail("dataset /events/ensemble", f"is not the ensembles {first}..{last - 1} of this file")
    if model == "dsmc":
        layout = dsmc_layout(reader, section, time, n)
    else:
        layout = tv06_layout(reader, model, section, n)

    observables = {name: _read_observable(reader, name, specs) for name, specs in layout["observables"].items()}
    for name in reader.names("/"):
        if name not in observables and name not in _NOT_OBSERVABLES and _has_mean_and_ci(reader, name):
            observables[name] = _read_other_observable(reader, name)

    events = {"ensemble": index}
    events.update({spec.name.rpartition("/")[2]: reader.dataset(spec) for spec in layout["events"]})
    for name in reader.names("events"):
        if name not in events and not (name == "species" and layout.get("species")):
            events[name] = read_dataset(f, f"events/{name}", path)

    steady = {name.partition("/")[2]: Observable(name=name, **fields)
              for name, fields in read_steady(reader, layout, n).items()}
    if "steady" in reader.names("/"):
        for name in reader.names("steady"):
            if name not in steady and _has_mean_and_ci(reader, f"steady/{name}"):
                steady[name] = _read_other_observable(reader, f"steady/{name}")

    for spec in layout["scalars"]:
        reader.dataset(spec)
    exact = {spec.name.rpartition("/")[2]: reader.dataset(spec) for spec in layout["exact"]}
    if "exact" in reader.names("/"):
        for name in reader.names("exact"):
            if name not in exact:
                exact[name] = read_dataset(f, f"exact/{name}", path)

    for owner, key, allowed, reason in layout["text"]:
        value = reader.text(owner, key, reason)
        if value not in allowed:
            reader.fail(f"attribute {key} of /{owner}", f"is {value!r}, not {' or '.join(map(repr, allowed))}")

    for name, specs in layout["histograms"].items():
        reader.group(name, specs[0].why)
        if model != "dsmc" and reader.integer(name, "samples", specs[0].why) > 0:
            specs = layout["histograms"][name] = [replace(spec, finite=True) for spec in specs]
        for spec in specs:
            reader.dataset(spec, read=False)  # shapes and dtypes now, the data when asked for

    reader.group("accumulators", why())
    for spec in layout["accumulators"]:
        reader.dataset(spec, read=False)  # for merging; read_run does not use their values
    for key, reason in layout.get("totals", ()):
        reader.integer("accumulators", key, reason)
    if layout["steady"]:
        reader.integer("accumulators", "steady_samples", why("dsmc.steady_from"))

    stored_model = reader.text("/", "model", why())
    if stored_model != model:
        reader.fail("attribute model", f"is {stored_model!r}, but the config says {model!r}")
    for key in ("version", "git_sha"):
        reader.text("/", key, why())
    seed = reader.integer("/", "seed", why())
    if config.get("seed") != seed:
        reader.fail("attribute seed", f"is {seed}, but the config says {config.get('seed')!r}")
    lambda_p = reader.number("/", "confidence_lambda_p", why())
    if lambda_p <= 0:
        reader.fail("attribute confidence_lambda_p", f"is {lambda_p}, not positive")

    histograms = [g for g in _HISTOGRAM_GROUPS if g in layout["histograms"] or g in reader.names("/")]
    species = read_species(reader, layout.get("species"), section, n, int(section.get("particles", 0)))
    manifest = read_manifest(reader)  # None: written before the manifest existed
    return Run(path=path, model=model, config=config, ensembles=ensembles, time=time, observables=observables,
               histograms=LazyHistograms(path, histograms, layout["histograms"]),
               events=events, steady=steady, exact=exact, provenance=prov, species=species, manifest=manifest)
