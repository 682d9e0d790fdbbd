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
run.complete is False for it.

read_run raises granboltz.io.RunReadError, naming the file and the dataset or attribute, for
anything that is not a complete output it can read: a file HDF5 cannot open or read (not HDF5,
truncated, a checksum failure), a checkpoint, an HDF5 file of another program, and a dataset or
attribute that every output of the file's model (and config) has but this file lacks, or has with
the wrong shape, dtype or non-finite values. The layout checked is what the simulator writes
(src/granboltz/io/output.cpp, dsmc/run.cpp, tv06/run.cpp; docs/output.md, docs/tv06.md). A
shard must have all of it too, for its own ensembles.
"""

from collections.abc import Mapping
from dataclasses import dataclass

import h5py
import numpy as np

from .io import (RunReadError, check_finite, open_run, provenance, read_attribute, read_config,
                 read_dataset, reading, text)

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

    def __init__(self, path, names, layouts=None):
        self._path, self._names, self._cache = str(path), tuple(names), {}
        # {group: [_Spec]}: the datasets read_run found in each group, checked again when read
        self._layouts = dict(layouts or {})

    def __getitem__(self, name):
        if name not in self._names:
            raise KeyError(f"{self._path} has no histogram {name!r} (it has: {', '.join(self._names) or 'none'})")
        if name not in self._cache:
            with open_run(self._path) as f:
                reader = _Reader(f, self._path, None)
                with reading(self._path, f"group /{name}"):
                    group = f.get(name)
                    if not isinstance(group, h5py.Group):
                        raise RunReadError(self._path, f"group /{name}", "missing (read_run found it)")
                    keys = [key for key in group if isinstance(group.get(key), h5py.Dataset)]
                out = {}
                for spec in self._layouts.get(name, ()):
                    out[spec.name.rpartition("/")[2]] = reader.dataset(spec)
                for key in keys:
                    if key not in out:
                        out[key] = read_dataset(f, f"{name}/{key}", self._path)
                self._cache[name] = out
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


# ----------------------------------------------------------------------------- the layout
# What the simulator writes, per model and config (io/output.cpp, io/record.cpp, dsmc/run.cpp,
# tv06/run.cpp). Doubles are float64, counters uint64, the exact sums int64 digits.
F8, U8, I8 = np.dtype("<f8"), np.dtype("<u8"), np.dtype("<i8")
_SUMS = (2, 72)  # exact sums: fixed-point digits of the sum and of the sum of squares
_DSMC_OBSERVABLES = (("density", ()), ("bulk_velocity", (3,)), ("temperature", ()), ("pressure_tensor", (3, 3)),
                     ("heat_flux", (3,)), ("fourth_moment", ()), ("crit", ()), ("temperature_uncentred", ()))
_DSMC_SCALARS = 20  # the scalars of one observation (dsmc/observables.hpp kNumScalars)
_TV06_OBSERVABLES = {"intruder": ("temperature_ratio", "mean_velocity"),
                     "needle": ("translational_temperature_ratio", "rotational_temperature_ratio", "R")}
_TV06_HISTOGRAMS = {"intruder": ("histogram",), "needle": ("velocity_histogram", "omega_histogram")}


@dataclass(frozen=True)
class _Spec:
    """A dataset every output of its kind has: dtype, shape (None: any), whether its values must
    be finite, and why it is required (for the message when it is missing)."""

    name: str
    dtype: np.dtype
    shape: tuple = None
    finite: bool = True
    why: str = ""


class _Reader:
    """Reads one open output, checking each dataset and attribute against its _Spec; every
    failure is RunReadError naming the file and the object."""

    def __init__(self, f, path, model):
        self.f, self.path, self.model = f, path, model

    def why(self, condition=""):
        return f"every {self.model} output{' with ' + condition if condition else ''} has it"

    def fail(self, name, problem):
        raise RunReadError(self.path, name, problem)

    def dataset(self, spec, read=True):
        label = f"dataset /{spec.name}"
        with reading(self.path, label):
            obj = self.f.get(spec.name)
            if obj is None:
                self.fail(label, f"missing ({spec.why})" if spec.why else "missing")
            if not isinstance(obj, h5py.Dataset):
                self.fail(label, "is a group, not a dataset")
            dtype = obj.dtype
            if dtype.kind != spec.dtype.kind or dtype.itemsize != spec.dtype.itemsize:
                self.fail(label, f"has dtype {dtype}, not {spec.dtype}")
            if spec.shape is not None and obj.shape != tuple(spec.shape):
                self.fail(label, f"has shape {obj.shape}, not {tuple(spec.shape)}")
            if not read:
                return None
            data = obj[()]
        if spec.finite:
            check_finite(data, self.path, label)
        return data

    def group(self, name, why):
        label = f"group /{name}"
        with reading(self.path, label):
            obj = self.f.get(name)
            if obj is None:
                self.fail(label, f"missing ({why})")
            if not isinstance(obj, h5py.Group):
                self.fail(label, "is a dataset, not a group")
            return obj

    def attribute(self, owner, key, why):
        where = "" if owner == "/" else f"/{owner}"
        with reading(self.path, f"attribute {key}" + (f" of {where}" if where else "")):
            obj = self.f if owner == "/" else self.group(owner, why)
            return read_attribute(obj, key, self.path, where, why)

    def integer(self, owner, key, why, minimum=0):
        value = self.attribute(owner, key, why)
        name = f"attribute {key}" + ("" if owner == "/" else f" of /{owner}")
        if not (isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_))):
            self.fail(name, f"is not an integer ({value!r})")
        if value < minimum:
            self.fail(name, f"is {value}, less than {minimum}")
        return int(value)

    def number(self, owner, key, why):
        value = self.attribute(owner, key, why)
        name = f"attribute {key}" + ("" if owner == "/" else f" of /{owner}")
        if not isinstance(value, (int, float, np.integer, np.floating)) or not np.isfinite(value):
            self.fail(name, f"is not a finite number ({value!r})")
        return float(value)

    def text(self, owner, key, why):
        value = self.attribute(owner, key, why)
        name = f"attribute {key}" + ("" if owner == "/" else f" of /{owner}")
        if not isinstance(value, (bytes, str)):
            self.fail(name, f"is not text ({value!r})")
        with reading(self.path, name):
            return text(value)

    def names(self, group):
        """The member names of a group the layout has already checked."""
        with reading(self.path, f"group /{group}"):
            return list(self.f[group])

    def is_dataset(self, name):
        with reading(self.path, f"/{name}"):
            return isinstance(self.f.get(name), h5py.Dataset)


def _section(config, path, model):
    section = config.get(model)
    if not isinstance(section, dict):
        raise RunReadError(path, "attribute config", f"has no mapping {model!r} (every {model} config has it)")
    return section


def _config_int(path, section, model, keys, default=0):
    """An integer of the config, e.g. dsmc.histogram.shells, or default if it is absent."""
    value = section
    for key in keys:
        value = value.get(key) if isinstance(value, dict) else None
        if value is None:
            return default
    if isinstance(value, bool) or not isinstance(value, int) or value < 0:
        raise RunReadError(path, "attribute config", f"{model}.{'.'.join(keys)} is not a non-negative integer ({value!r})")
    return value


def _shard(path, prov, ensembles):
    """(first, last) ensemble of the file from provenance shard "i/count" (config.hpp
    first_ensemble/last_ensemble); every output of `granboltz run` has it, a merged file has
    merged_from instead and holds every ensemble."""
    if "merged_from" in prov:
        return 0, ensembles
    name = "attribute shard of /provenance"
    if "shard" not in prov:
        raise RunReadError(path, name, "missing (every output of granboltz run has it; a merged file has merged_from)")
    index, slash, count = str(prov["shard"]).partition("/")
    if not (slash and index.isdigit() and count.isdigit() and int(index) < int(count)):
        raise RunReadError(path, name, f"is not \"index/count\" with index < count ({prov['shard']!r})")
    index, count = int(index), int(count)
    return ensembles * index // count, ensembles * (index + 1) // count


def _check_provenance(path, prov):
    for key, kind in (("threads", int), ("wall_seconds", float)):
        if key in prov:
            value = prov[key]
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not np.isfinite(value) \
                    or (kind is int and not isinstance(value, int)):
                raise RunReadError(path, f"attribute {key} of /provenance", f"is not a number ({value!r})")


def _observable_specs(name, trailing, rows, why, per_ensemble=None):
    shape = tuple(rows) + tuple(trailing)
    specs = [_Spec(f"{name}/{key}", F8, shape, True, why) for key in ("mean", "ci", "variance")]
    if per_ensemble is not None:
        specs.append(_Spec(f"{name}/per_ensemble", F8, (per_ensemble,), True, why))
    return specs


def _read_observable(reader, name, specs):
    values = {spec.name.rpartition("/")[2]: reader.dataset(spec) for spec in specs}
    return Observable(name=name, mean=values["mean"], ci=values["ci"],
                      variance=values.get("variance"), per_ensemble=values.get("per_ensemble"))


def _read_other_observable(reader, name):
    """An observable group the layout does not name (a newer simulator's): read as it is."""
    f, path = reader.f, reader.path
    with reading(path, f"group /{name}"):
        group = f[name]
        members = set(group)
    return Observable(name=name, mean=read_dataset(f, f"{name}/mean", path),
                      ci=read_dataset(f, f"{name}/ci", path),
                      variance=read_dataset(f, f"{name}/variance", path) if "variance" in members else None,
                      per_ensemble=read_dataset(f, f"{name}/per_ensemble", path) if "per_ensemble" in members else None)


def _has_mean_and_ci(reader, name):
    with reading(reader.path, f"group /{name}"):
        obj = reader.f.get(name)
        return isinstance(obj, h5py.Group) and "mean" in obj and "ci" in obj


def _dsmc_layout(reader, section, rows, n):
    """Observables, events, steady, histogram and accumulators of a DSMC output (dsmc/run.cpp
    present_dsmc, dsmc_layout): {"observables": {name: [_Spec]}, ...}."""
    path, why = reader.path, reader.why
    P = _config_int(path, section, "dsmc", ("moments",), 4)
    K1 = _config_int(path, section, "dsmc", ("histogram", "shells")) + 1
    shells = K1 > 1
    steady = section.get("steady_from") is not None
    swpm = section.get("weights") is not None
    R = rows
    moments = [(f"moment_{2 * p}", ()) for p in range(1, P + 1)]
    m_why = why("dsmc.moments > 0")
    out = {"observables": {name: _observable_specs(name, trail, (R,), why()) for name, trail in _DSMC_OBSERVABLES}}
    out["observables"].update({name: _observable_specs(name, trail, (R,), m_why) for name, trail in moments})
    events = [_Spec(f"events/{key}", U8, (n,), True, why()) for key in ("collisions", "fictitious", "kicks")]
    events.append(_Spec("events/u_max_final", F8, (n,), True, why()))
    if swpm:
        events += [_Spec(f"events/{key}", U8, (n,), True, why("dsmc.weights")) for key in ("reductions", "particles_final")]
    out["events"] = events
    acc = [_Spec("accumulators/series", I8, (R * _DSMC_SCALARS,) + _SUMS, True, why())]
    if P:
        acc.append(_Spec("accumulators/moment_series", I8, (R * P,) + _SUMS, True, m_why))
    out["steady"] = {}
    if steady:
        s_why = why("dsmc.steady_from")
        out["steady"] = {f"steady/{name}": _observable_specs(f"steady/{name}", trail, (), s_why)
                         for name, trail in _DSMC_OBSERVABLES}
        out["steady"].update({f"steady/{name}": _observable_specs(f"steady/{name}", trail, (), why("dsmc.steady_from and dsmc.moments > 0"))
                              for name, trail in moments})
        acc.append(_Spec("accumulators/steady", I8, (_DSMC_SCALARS,) + _SUMS, True, s_why))
        if P:
            acc.append(_Spec("accumulators/moment_steady", I8, (P,) + _SUMS, True, s_why))
    out["histograms"] = {}
    if shells:
        h_why = why("dsmc.histogram")
        out["histograms"]["histogram"] = [_Spec("histogram/edges", F8, (K1,), True, h_why),
                                          _Spec("histogram/mean", F8, (R, K1), True, h_why),
                                          _Spec("histogram/ci", F8, (R, K1), True, h_why),
                                          _Spec("histogram/counts", U8, (R, K1), True, h_why)]
        acc += [_Spec("accumulators/histogram", U8, (R * K1,), True, h_why),
                _Spec("accumulators/histogram_sq", U8, (R * K1, 2), True, h_why)]
        if steady:
            sh_why = why("dsmc.histogram and dsmc.steady_from")
            out["steady"]["steady/histogram"] = [_Spec("steady/histogram/mean", F8, (K1,), True, sh_why),
                                                 _Spec("steady/histogram/ci", F8, (K1,), True, sh_why)]
            acc.append(_Spec("accumulators/histogram_steady", I8, (K1,) + _SUMS, True, sh_why))
        if swpm:
            acc.append(_Spec("accumulators/histogram_weight", I8, (R * K1,) + _SUMS, True, why("dsmc.histogram and dsmc.weights")))
    out["accumulators"] = acc
    out["scalars"], out["exact"] = [], []
    return out


def _tv06_layout(reader, model, section, n):
    """Observables, events, exact values, histograms and accumulators of an intruder or needle
    output (tv06/run.cpp tv06_layout, present_tv06)."""
    path, why = reader.path, reader.why
    out = {"observables": {name: _observable_specs(name, (), (), why(), per_ensemble=n)
                           for name in _TV06_OBSERVABLES[model]}}
    events = [_Spec(f"events/{key}", U8, (n,), True, why()) for key in ("collisions", "samples")]
    events.append(_Spec("events/time", F8, (n,), True, why()))
    dsmc_method = model == "intruder" and section.get("method") == "dsmc"
    if model == "needle":
        events.append(_Spec("events/fictitious", U8, (n,), True, why()))
    if dsmc_method:
        m_why = why("intruder.method: dsmc")
        events += [_Spec("events/fictitious", U8, (n,), True, m_why), _Spec("events/majorant_exceeded", U8, (n,), True, m_why),
                   _Spec("events/omega_max_final", F8, (n,), True, m_why)]
    out["events"] = events
    out["scalars"] = [_Spec(name, F8, (), True, why()) for name in ("bath_temperature", "sample_interval")]
    exact = []
    if model == "intruder":
        bath = section.get("bath")
        gaussian = isinstance(bath, dict) and bath.get("kind") == "gaussian"
        if gaussian or ("mass" in section and section.get("mass") == section.get("alpha")):
            exact.append(_Spec("exact/temperature_ratio", F8, (), True, why("a Gaussian bath or mass = alpha")))
    elif section.get("alpha") == 1:
        exact += [_Spec(f"exact/{name}", F8, (), True, why("alpha = 1")) for name in _TV06_OBSERVABLES[model]]
    out["exact"] = exact
    acc = [_Spec(f"accumulators/{name}", I8, (1,) + _SUMS, True, why()) for name in _TV06_OBSERVABLES[model]]
    out["histograms"], out["totals"] = {}, []
    for name in _TV06_HISTOGRAMS[model]:
        bins = _config_int(path, section, model, (name, "bins"))
        if not bins:
            continue
        h_why = why(f"{model}.{name}")
        # density and ci are 0/0 when no sample was taken: they may be NaN
        out["histograms"][name] = [_Spec(f"{name}/edges", F8, (bins + 1,), True, h_why),
                                   _Spec(f"{name}/counts", U8, (bins,), True, h_why),
                                   _Spec(f"{name}/overflow", U8, (2,), True, h_why),
                                   _Spec(f"{name}/density", F8, (bins,), False, h_why),
                                   _Spec(f"{name}/ci", F8, (bins,), False, h_why)]
        acc += [_Spec(f"accumulators/{name}", U8, (bins,), True, h_why),
                _Spec(f"accumulators/{name}_sq", U8, (bins, 2), True, h_why)]
        out["totals"] += [(f"{name}_{key}", h_why) for key in ("below", "above", "samples")]
    out["accumulators"] = acc
    out["steady"] = {}
    return out


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
        reader = _Reader(f, path, model)
        with reading(path, "the file"):
            return _read(reader, config, model)


def _read(reader, config, model):
    f, path, why = reader.f, reader.path, reader.why
    section = _section(config, path, model)
    ensembles = reader.integer("/", "ensembles", why(), minimum=1)
    if config.get("ensembles") != ensembles:
        reader.fail("attribute ensembles", f"is {ensembles}, but the config says {config.get('ensembles')!r}")
    time = None
    if model == "dsmc":
        time = reader.dataset(_Spec("time", F8, None, True, why()))
        if time.ndim != 1 or time.size == 0:
            reader.fail("dataset /time", f"has shape {time.shape}, not [M+1]")
        if np.any(np.diff(time) <= 0):
            reader.fail("dataset /time", "is not increasing")
    reader.group("provenance", why())
    prov = provenance(f, path)
    _check_provenance(path, prov)
    first, last = _shard(path, prov, ensembles)
    n = last - first
    reader.group("events", why())
    index = reader.dataset(_Spec("events/ensemble", U8, (n,), True, why()))
    if not np.array_equal(index, np.arange(first, last)):
        reader.fail("dataset /events/ensemble", f"is not the ensembles {first}..{last - 1} of this file")
    if model == "dsmc":
        layout = _dsmc_layout(reader, section, time.size, n)
    else:
        layout = _tv06_layout(reader, model, section, n)

    observables = {name: _read_observable(reader, name, specs) for name, specs in layout["observables"].items()}
    for name in reader.names("/"):
        if name not in observables and name not in _NOT_OBSERVABLES and _has_mean_and_ci(reader, name):
            observables[name] = _read_other_observable(reader, name)

    events = {"ensemble": index}
    events.update({spec.name.rpartition("/")[2]: reader.dataset(spec) for spec in layout["events"]})
    for name in reader.names("events"):
        if name not in events:
            events[name] = read_dataset(f, f"events/{name}", path)

    steady = {}
    if layout["steady"]:
        reader.group("steady", why("dsmc.steady_from"))
        reader.integer("steady", "samples", why("dsmc.steady_from"), minimum=1)
        reader.number("steady", "from", why("dsmc.steady_from"))
        if "steady/histogram" in layout["steady"]:
            reader.integer("steady/histogram", "rows", why("dsmc.histogram and dsmc.steady_from"), minimum=1)
        steady = {name.rpartition("/")[2]: _read_observable(reader, name, specs) for name, specs in layout["steady"].items()}
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

    for name, specs in layout["histograms"].items():
        reader.group(name, specs[0].why)
        for spec in specs:
            reader.dataset(spec, read=False)  # shapes and dtypes now, the data when asked for
        if model != "dsmc":
            reader.integer(name, "samples", specs[0].why)

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
    return Run(path=path, model=model, config=config, ensembles=ensembles, time=time, observables=observables,
               histograms=LazyHistograms(path, histograms, layout["histograms"]),
               events=events, steady=steady, exact=exact, provenance=prov)
