"""The layout of granboltz outputs that granboltz.output.run.read_run checks: per model and config, the
datasets every output has with their dtypes and shapes (Spec); granboltz.output.reader.Reader checks a
dataset or an attribute against it and raises RunReadError naming the file and the object, and
granboltz.output.intervals adds the steady-state intervals.

What the simulator writes: src/granboltz/app/output.cpp (root and provenance attributes),
record/record.cpp (accumulators, events), dsmc/run.cpp (present_dsmc, dsmc_layout), tv06/run.cpp
(present_tv06, tv06_layout); docs/output.md and docs/tv06.md describe it.
"""

from dataclasses import dataclass

import numpy as np

from .io import RunReadError
from .reader import Reader  # noqa: F401 - older callers import it from here

# Doubles are float64, counters uint64, the exact sums int64 digits.
F8, U8, I8 = np.dtype("<f8"), np.dtype("<u8"), np.dtype("<i8")
SUMS = (2, 72)  # exact sums: fixed-point digits of the sum and of the sum of squares
DSMC_OBSERVABLES = (("density", ()), ("bulk_velocity", (3,)), ("temperature", ()), ("pressure_tensor", (3, 3)),
                     ("heat_flux", (3,)), ("fourth_moment", ()), ("crit", ()), ("temperature_uncentred", ()))
DSMC_SCALARS = 20  # the scalars of one observation (dsmc/observables.hpp kNumScalars)
_TV06_OBSERVABLES = {"intruder": ("temperature_ratio", "mean_velocity"),
                     "needle": ("translational_temperature_ratio", "rotational_temperature_ratio", "R")}
_TV06_HISTOGRAMS = {"intruder": ("histogram",), "needle": ("velocity_histogram", "omega_histogram")}


@dataclass(frozen=True)
class Spec:
    """A dataset every output of its kind has: dtype, shape (None: any), whether its values must
    be finite, and why it is required (for the message when it is missing)."""

    name: str
    dtype: np.dtype
    shape: tuple = None
    finite: bool = True
    why: str = ""


def config_section(config, path, model):
    """The model's mapping of the config (config["dsmc"], ...); RunReadError if it has none."""
    section = config.get(model)
    if not isinstance(section, dict):
        raise RunReadError(path, "attribute config", f"has no mapping {model!r} (every {model} config has it)")
    return section


def config_int(path, section, model, keys, default=0):
    """An integer of the config, e.g. dsmc.histogram.shells, or default if it is absent."""
    value = section
    for key in keys:
        value = value.get(key) if isinstance(value, dict) else None
        if value is None:
            return default
    if isinstance(value, bool) or not isinstance(value, int) or value < 0:
        raise RunReadError(path, "attribute config",
                           f"{model}.{'.'.join(keys)} is not a non-negative integer ({value!r})")
    return value


def shard_range(path, prov, ensembles):
    """(first, last) ensemble of the file from provenance shard "i/count" (config.hpp
    first_ensemble/last_ensemble); every output of `granboltz run` has it, a merged file has
    merged_from instead and holds every ensemble."""
    if "merged_from" in prov:
        return 0, ensembles
    name = "attribute shard of /provenance"
    if "shard" not in prov:
        raise RunReadError(path, name,
                           "missing (every output of granboltz run has it; a merged file has merged_from)")
    index, slash, count = str(prov["shard"]).partition("/")
    if not (slash and index.isdigit() and count.isdigit() and int(index) < int(count)):
        raise RunReadError(path, name, f"is not \"index/count\" with index < count ({prov['shard']!r})")
    index, count = int(index), int(count)
    return ensembles * index // count, ensembles * (index + 1) // count


def check_provenance(path, prov):
    """RunReadError unless /provenance's threads and wall_seconds, where present, are numbers."""
    for key, kind in (("threads", int), ("wall_seconds", float)):
        if key in prov:
            value = prov[key]
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not np.isfinite(value) \
                    or (kind is int and not isinstance(value, int)):
                raise RunReadError(path, f"attribute {key} of /provenance", f"is not a number ({value!r})")


def observable_specs(name, trailing, rows, why, per_ensemble=None):
    """The Specs of one observable group: mean, ci, variance of shape rows + trailing, and
    per_ensemble [N] for TV06."""
    shape = tuple(rows) + tuple(trailing)
    specs = [Spec(f"{name}/{key}", F8, shape, True, why) for key in ("mean", "ci", "variance")]
    if per_ensemble is not None:
        specs.append(Spec(f"{name}/per_ensemble", F8, (per_ensemble,), True, why))
    return specs


def config_flag(path, section, model, keys):
    """A true/false of the config, e.g. dsmc.histogram.component (False if absent)."""
    value = section
    for key in keys:
        value = value.get(key) if isinstance(value, dict) else None
    if value is None:
        return False
    if not isinstance(value, bool):
        raise RunReadError(path, "attribute config", f"{model}.{'.'.join(keys)} is not true or false ({value!r})")
    return value


def _histogram_specs(out, acc, name, R, K1, steady, swpm, h_why, sh_why):
    out["histograms"][name] = [Spec(f"{name}/edges", F8, (K1,), True, h_why),
                               Spec(f"{name}/mean", F8, (R, K1), True, h_why),
                               Spec(f"{name}/ci", F8, (R, K1), True, h_why),
                               Spec(f"{name}/counts", U8, (R, K1), True, h_why)]
    acc += [Spec(f"accumulators/{name}", U8, (R * K1,), True, h_why),
            Spec(f"accumulators/{name}_sq", U8, (R * K1, 2), True, h_why)]
    if steady:
        out["steady"][f"steady/{name}"] = [Spec(f"steady/{name}/mean", F8, (K1,), True, sh_why),
                                           Spec(f"steady/{name}/ci", F8, (K1,), True, sh_why)]
        out["steady_rows"].append((f"steady/{name}", sh_why))
        acc.append(Spec(f"accumulators/{name}_steady", I8, (K1,) + SUMS, True, sh_why))
    if swpm:
        acc.append(Spec(f"accumulators/{name}_weight", I8, (R * K1,) + SUMS, True, h_why))


def dsmc_layout(reader, section, time, n):
    """Observables, events, steady, histogram and accumulators of a DSMC output (dsmc/run.cpp
    present_dsmc, dsmc_layout): {"observables": {name: [Spec]}, ...}; "intervals": {steady
    group: IntervalSpec}, "text": [(owner, key, allowed values, why)] and "steady_rows":
    [(group, why)] of the groups with attribute rows (/steady: granboltz.output.intervals).

    What a file has depends on when its simulator was built, and the resolved config tells: one
    with dsmc.histogram.center has attribute center on the histograms. Optional, so that files of
    older simulators still read: /a2, /a3 (mean and ci, no variance), read as groups the layout
    does not name. A mixture (dsmc.species) has out["species"] (granboltz.output.species.species_layout),
    rough spheres (dsmc.roughness) /temperature_rotational and its steady average, and both
    their stored ratios (granboltz.output.ratios: /theta, /temperature_ratio/<a>_over_<b>)."""
    path, why = reader.path, reader.why
    P = config_int(path, section, "dsmc", ("moments",), 4)
    K1 = config_int(path, section, "dsmc", ("histogram", "shells")) + 1
    shells = K1 > 1
    component = shells and config_flag(path, section, "dsmc", ("histogram", "component"))
    steady = section.get("steady_from") is not None
    swpm = section.get("weights") is not None
    R = time.size
    moments = [(f"moment_{2 * p}", ()) for p in range(1, P + 1)]
    m_why = why("dsmc.moments > 0")
    out = {"observables": {name: observable_specs(name, trail, (R,), why()) for name, trail in DSMC_OBSERVABLES}}
    out["observables"].update({name: observable_specs(name, trail, (R,), m_why) for name, trail in moments})
    rough = section.get("roughness") is not None
    if rough:  # rough spheres: the rotational temperature beside the translational /temperature
        out["observables"]["temperature_rotational"] = observable_specs("temperature_rotational", (), (R,),
                                                                        why("dsmc.roughness"))
    events = [Spec(f"events/{key}", U8, (n,), True, why()) for key in ("collisions", "fictitious", "kicks")]
    events.append(Spec("events/u_max_final", F8, (n,), True, why()))
    if swpm:
        events += [Spec(f"events/{key}", U8, (n,), True, why("dsmc.weights"))
                   for key in ("reductions", "particles_final")]
    out["events"] = events
    acc = [Spec("accumulators/series", I8, (R * DSMC_SCALARS,) + SUMS, True, why())]
    if P:
        acc.append(Spec("accumulators/moment_series", I8, (R * P,) + SUMS, True, m_why))
    out["steady"], out["intervals"], out["text"], out["steady_rows"], out["histograms"] = {}, {}, [], [], {}
    if steady:
        from .intervals import steady_layout  # it builds on this module

        steady_layout(reader, section, time, n, P, moments + ([("temperature_rotational", ())] if rough else []),
                      out, acc)
    if shells:
        h_why = why("dsmc.histogram")
        sh_why = why("dsmc.histogram and dsmc.steady_from")
        _histogram_specs(out, acc, "histogram", R, K1, steady, swpm, h_why, sh_why)
        center = section["histogram"].get("center")
        if center is not None:  # resolved configs say it since dsmc.histogram.center exists
            out["text"].append(("histogram", "center", (center,), why("dsmc.histogram.center")))
        if component:
            c_why = why("dsmc.histogram.component")
            _histogram_specs(out, acc, "histogram_component", R, K1, steady, swpm, c_why,
                             why("dsmc.histogram.component and dsmc.steady_from"))
            out["text"].append(("histogram_component", "center", ("bulk",), c_why))  # always about V(t)
    out["accumulators"] = acc
    out["scalars"], out["exact"] = [], []
    from .species import species_layout  # it builds on this module

    out["species"] = species_layout(reader, section, time, n, P, steady)
    from .ratios import ratio_layout  # it builds on this module

    ratio_layout(reader, section, R, steady, out, acc)
    return out


def tv06_layout(reader, model, section, n):
    """Observables, events, exact values, histograms and accumulators of an intruder or needle
    output (tv06/run.cpp tv06_layout, present_tv06)."""
    path, why = reader.path, reader.why
    out = {"observables": {name: observable_specs(name, (), (), why(), per_ensemble=n)
                           for name in _TV06_OBSERVABLES[model]}}
    events = [Spec(f"events/{key}", U8, (n,), True, why()) for key in ("collisions", "samples")]
    events.append(Spec("events/time", F8, (n,), True, why()))
    dsmc_method = model == "intruder" and section.get("method") == "dsmc"
    if model == "needle":
        events.append(Spec("events/fictitious", U8, (n,), True, why()))
    if dsmc_method:
        m_why = why("intruder.method: dsmc")
        events += [Spec("events/fictitious", U8, (n,), True, m_why),
                   Spec("events/majorant_exceeded", U8, (n,), True, m_why),
                   Spec("events/omega_max_final", F8, (n,), True, m_why)]
    out["events"] = events
    out["scalars"] = [Spec(name, F8, (), True, why()) for name in ("bath_temperature", "sample_interval")]
    exact = []
    if model == "intruder":
        bath = section.get("bath")
        gaussian = isinstance(bath, dict) and bath.get("kind") == "gaussian"
        if gaussian or ("mass" in section and section.get("mass") == section.get("alpha")):
            exact.append(Spec("exact/temperature_ratio", F8, (), True, why("a Gaussian bath or mass = alpha")))
    elif section.get("alpha") == 1:
        exact += [Spec(f"exact/{name}", F8, (), True, why("alpha = 1")) for name in _TV06_OBSERVABLES[model]]
    out["exact"] = exact
    acc = [Spec(f"accumulators/{name}", I8, (1,) + SUMS, True, why()) for name in _TV06_OBSERVABLES[model]]
    out["histograms"], out["totals"] = {}, []
    for name in _TV06_HISTOGRAMS[model]:
        bins = config_int(path, section, model, (name, "bins"))
        if not bins:
            continue
        h_why = why(f"{model}.{name}")
        # density and ci are 0/0 when no sample was taken: NaN allowed then only (read_run)
        out["histograms"][name] = [Spec(f"{name}/edges", F8, (bins + 1,), True, h_why),
                                   Spec(f"{name}/counts", U8, (bins,), True, h_why),
                                   Spec(f"{name}/overflow", U8, (2,), True, h_why),
                                   Spec(f"{name}/density", F8, (bins,), False, h_why),
                                   Spec(f"{name}/ci", F8, (bins,), False, h_why)]
        acc += [Spec(f"accumulators/{name}", U8, (bins,), True, h_why),
                Spec(f"accumulators/{name}_sq", U8, (bins, 2), True, h_why)]
        out["totals"] += [(f"{name}_{key}", h_why) for key in ("below", "above", "samples")]
    out["accumulators"] = acc
    out["steady"], out["intervals"], out["text"], out["steady_rows"] = {}, {}, [], []
    return out
