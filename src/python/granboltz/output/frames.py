"""A run as data: an xarray Dataset or a pandas DataFrame of its observables with their
intervals, and a quick look at one observable (Run.to_xarray, Run.to_dataframe, Run.plot).

Names: each observable `<name>` is its ensemble mean and `<name>_ci` its confidence half-width
(lambda_p = 3.2, as everywhere in the package); the steady averages are `steady_<name>` and
`steady_<name>_ci` (0-d, or per component); a mixture's species observables carry a `species`
dimension (`species_<name>`). Components: `component` (x, y, z) for vectors, `i`, `j` for tensors;
in d = 2 only x, y. The config is flattened into attributes with dotted keys ("dsmc.alpha"), beside
`model`, `ensembles` and `path`.
"""

import numbers

import numpy as np

_AXES = "xyz"


def flat_config(config, prefix=""):
    """{"dsmc.alpha": 0.5, ...}: the config's leaves under dotted keys; lists and other values
    that a netCDF attribute cannot hold as they are become their repr."""
    out = {}
    for key, value in (config or {}).items():
        name = f"{prefix}{key}"
        if isinstance(value, dict):
            out.update(flat_config(value, name + "."))
        elif isinstance(value, (str, bool)) or (isinstance(value, numbers.Number) and not isinstance(value, complex)):
            out[name] = int(value) if isinstance(value, bool) else value
        else:
            out[name] = repr(value)
    return out


def _dimension(run):
    section = run.config.get(run.model, {}) if isinstance(run.config, dict) else {}
    d = section.get("dimension", 3) if isinstance(section, dict) else 3
    return d if d in (2, 3) else 3


def _dims(shape, leading, d):
    """The dimension names of an array of `shape` after `leading` (e.g. ("time",))."""
    extra = len(shape) - len(leading)
    if extra == 0:
        return leading, {}
    if extra == 1 and shape[-1] == 3:
        return leading + ("component",), {"component": list(_AXES)}
    if extra == 2 and shape[-2:] == (3, 3):
        return leading + ("i", "j"), {"i": list(_AXES), "j": list(_AXES)}
    return leading + tuple(f"dim_{k}" for k in range(extra)), {}


def _trim(values, dims, d):
    """The d < 3 components of vectors and tensors dropped (their z rows are 0 by construction)."""
    if d == 3:
        return values
    index = tuple(slice(0, d) if name in ("component", "i", "j") else slice(None) for name in dims)
    return values[index]


def to_xarray(run):
    """xarray.Dataset of the run (module docstring)."""
    import xarray as xr

    d = _dimension(run)
    variables, coords = {}, {}
    series = run.time is not None and np.ndim(run.time) == 1 and len(run.time) > 0
    if series:
        coords["time"] = np.asarray(run.time, dtype=float)

    def add(name, obs, leading, per_lead=None):
        mean = np.asarray(obs.mean, dtype=float)
        dims, extra = _dims(mean.shape, leading, d)
        for key, labels in extra.items():
            coords[key] = labels[:d] if key in ("component", "i", "j") else labels
        variables[name] = (dims, _trim(mean, dims, d))
        variables[name + "_ci"] = (dims, _trim(np.asarray(obs.ci, dtype=float), dims, d))

    for name, obs in run.observables.items():
        leading = ("time",) if series and np.ndim(obs.mean) >= 1 and np.shape(obs.mean)[0] == len(run.time) else ()
        add(name, obs, leading)
    for name, obs in (run.steady or {}).items():
        add("steady_" + name.replace("/", "_"), obs, ())
    if run.species:
        names = list(run.species)
        coords["species"] = names
        common = set.intersection(*(set(sp.observables) for sp in run.species.values()))
        for obs_name in sorted(common):
            first = run.species[names[0]].observables[obs_name]
            if not (series and np.ndim(first.mean) >= 1 and np.shape(first.mean)[0] == len(run.time)):
                continue
            stacked = np.stack([np.asarray(run.species[s].observables[obs_name].mean, dtype=float) for s in names])
            cis = np.stack([np.asarray(run.species[s].observables[obs_name].ci, dtype=float) for s in names])
            dims, extra = _dims(stacked.shape, ("species", "time"), d)
            for key, labels in extra.items():
                coords[key] = labels[:d]
            variables["species_" + obs_name] = (dims, _trim(stacked, dims, d))
            variables["species_" + obs_name + "_ci"] = (dims, _trim(cis, dims, d))
    attrs = {"model": run.model, "ensembles": int(run.ensembles), "path": str(run.path)}
    attrs.update(flat_config(run.config))
    return xr.Dataset(variables, coords=coords, attrs=attrs)


def to_dataframe(run):
    """pandas.DataFrame: one row per observation time (index `time`), one column per scalar
    observable and per component of a vector or tensor (`pressure_tensor_xy`), each with its
    `_ci` column; a mixture's species as `<name>_<species>`. The steady averages are in
    run.steady (and in to_xarray); TV06 runs, which have no time series, give one row of their
    time averages. The config is in `frame.attrs`."""
    import pandas as pd

    d = _dimension(run)
    columns = {}

    def add(label, mean, ci):
        mean, ci = np.asarray(mean, dtype=float), np.asarray(ci, dtype=float)
        extra = mean.shape[1:] if rows else mean.shape
        if not extra:
            columns[label], columns[label + "_ci"] = (mean, ci) if rows else (float(mean), float(ci))
            return
        for idx in np.ndindex(*extra):
            if any(k >= d for k in idx):
                continue
            suffix = "".join(_AXES[k] for k in idx)
            key = (slice(None),) + idx if rows else idx
            columns[f"{label}_{suffix}"] = mean[key] if rows else float(mean[key])
            columns[f"{label}_{suffix}_ci"] = ci[key] if rows else float(ci[key])

    rows = run.time is not None and np.ndim(run.time) == 1 and len(run.time) > 0
    for name, obs in run.observables.items():
        if rows and not (np.ndim(obs.mean) >= 1 and np.shape(obs.mean)[0] == len(run.time)):
            continue
        add(name, obs.mean, obs.ci)
    for sp_name, sp in (run.species or {}).items():
        for name, obs in sp.observables.items():
            if rows and np.ndim(obs.mean) >= 1 and np.shape(obs.mean)[0] == len(run.time):
                add(f"{name}_{sp_name}", obs.mean, obs.ci)
    if rows:
        frame = pd.DataFrame(columns, index=pd.Index(np.asarray(run.time, dtype=float), name="time"))
    else:
        frame = pd.DataFrame({k: [v] for k, v in columns.items()})
    frame.attrs.update({"model": run.model, "ensembles": int(run.ensembles), "path": str(run.path)})
    frame.attrs.update(flat_config(run.config))
    return frame


def plot(run, observable="temperature", theory=None, ax=None, label=None, component=None):
    """A quick look: the observable's mean against time with its confidence band, in the house
    style, and `theory` dashed: a number, an array over run.time, or a function of the time
    array. component: an index (vector) or a pair (tensor) for a non-scalar observable, e.g.
    plot("pressure_tensor", component=(0, 1)). Returns the axes (a new figure unless `ax`)."""
    from .plotting import house_style

    obs = run.observables.get(observable) if isinstance(observable, str) else observable
    if obs is None:
        raise KeyError(f"the run has no observable {observable!r} (it has {', '.join(run.observables)})")
    mean, ci = np.asarray(obs.mean, dtype=float), np.asarray(obs.ci, dtype=float)
    if component is not None:
        idx = (slice(None),) + (tuple(component) if isinstance(component, (tuple, list)) else (component,))
        mean, ci = mean[idx], ci[idx]
    if mean.ndim != 1 or run.time is None or len(run.time) != len(mean):
        raise ValueError(f"plot: {observable!r} is not a scalar time series (shape {mean.shape}); "
                         "give component= for a vector or tensor")
    import matplotlib.pyplot as plt

    with plt.rc_context(house_style()):
        if ax is None:
            _, ax = plt.subplots(figsize=(4.0, 2.8))
        t = np.asarray(run.time, dtype=float)
        name = observable if isinstance(observable, str) else obs.name
        line, = ax.plot(t, mean, label=label or name)
        ax.fill_between(t, mean - ci, mean + ci, color=line.get_color(), alpha=0.25, linewidth=0)
        if theory is not None:
            values = theory(t) if callable(theory) else theory
            ax.plot(t, np.broadcast_to(np.asarray(values, dtype=float), t.shape), "--", color="black",
                    label="theory")
        ax.set_xlabel("t")
        ax.set_ylabel(name if component is None else f"{name}{list(np.atleast_1d(component))}")
        ax.legend()
    return ax


def plot_columns(table, x, y, ax=None, theory=None):
    """Column y of a table (a DataFrame, e.g. Study.table()) against column x, with the column
    `<y>_ci` as error bars where present and `theory(x values)` dashed, sorted by x; the axes."""
    for name in (x, y):
        if name not in table.columns:
            raise KeyError(f"the table has no column {name!r} (it has {', '.join(map(str, table.columns))})")
    import matplotlib.pyplot as plt

    from .plotting import house_style

    rows = table.sort_values(x)
    xs = rows[x].to_numpy(dtype=float)
    with plt.rc_context(house_style()):
        if ax is None:
            _, ax = plt.subplots(figsize=(4.0, 2.8))
        err = rows[y + "_ci"].to_numpy(dtype=float) if y + "_ci" in rows.columns else None
        ax.errorbar(xs, rows[y].to_numpy(dtype=float), yerr=err, fmt="o", markersize=3, capsize=2, label=y)
        if theory is not None:
            grid = np.linspace(xs.min(), xs.max(), 200) if len(xs) > 1 else xs
            ax.plot(grid, theory(grid), "--", color="black", label="theory")
        ax.set_xlabel(x)
        ax.set_ylabel(y)
        ax.legend()
    return ax
