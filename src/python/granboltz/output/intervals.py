"""The steady-state intervals of a DSMC output (docs/output.md, Steady state), as read_run checks
and reads them: each /steady/<observable>'s sigma with its estimator's attributes (estimator,
tau_int, effective_samples, samples, from, block_rows), with steady_ci: independent its batch
subgroup (the honest interval of the same run), /steady/a2 and a3, and the per-ensemble sums
behind them. Builds on granboltz.output.layout (Spec, Reader); read_run gives them as Observable.sigma,
.estimator, .tau_int, .effective_samples, .block_rows and .batch (an Interval).
"""

from dataclasses import dataclass, replace

import numpy as np

from .io import check_finite
from .layout import DSMC_OBSERVABLES, DSMC_SCALARS, SUMS, F8, I8, Spec, observable_specs

_STEADY_MIN_ENSEMBLES = 10  # from this many ensembles the batch estimator is their spread (dsmc/run.hpp)


@dataclass(frozen=True)
class Interval:
    """A standard error sigma and its confidence half-width ci from one estimator of a steady
    average (docs/output.md, Steady state): estimator "ensembles", "blocking" or "independent";
    tau_int, the integrated autocorrelation time in rows, and effective_samples = variance /
    sigma^2 (None where the file has none, e.g. for a2 and a3); block_rows, the block length
    of blocking. NaN sigma, ci, tau_int and effective_samples: fewer than two ensembles, whose
    spread the ensembles estimator cannot measure."""

    sigma: np.ndarray
    ci: np.ndarray
    estimator: str
    tau_int: float = None
    effective_samples: float = None
    block_rows: int = None


@dataclass(frozen=True)
class IntervalSpec:
    """The standard error of a /steady group (docs/output.md, Steady state): dataset sigma of
    `shape` (and ci, for a batch subgroup) with the attributes estimator (one of `estimators`),
    `keys` (tau_int, effective_samples), samples, from, and block_rows for blocking. required:
    every output of this config has it; otherwise it is read, and checked, where present.
    batch: the IntervalSpec of the group's batch subgroup (steady_ci: independent), or None."""

    group: str
    shape: tuple
    required: bool
    estimators: tuple
    why: str = ""
    keys: tuple = ("tau_int", "effective_samples")
    ci: bool = False
    batch: "IntervalSpec" = None
    levels: int = 0  # the blocking levels: block_rows is 2^l, l < levels


def block_levels(rows):
    """The blocking levels of the steady state (dsmc/run.cpp steady_block_levels): block lengths
    2^l while an ensemble's `rows` hold two full blocks."""
    levels = 0
    while levels < 63 and (rows >> levels) >= 2:
        levels += 1
    return levels


def steady_layout(reader, section, time, n, P, moments, out, acc):
    """The /steady part of layout.dsmc_layout: observables, their intervals, a2 and a3, accumulators.

    What a file has depends on when its simulator was built. A resolved config with
    dsmc.steady_ci has sigma and the estimator's attributes on every steady observable (and
    /accumulators/steady_ensemble, steady_blocks with batch); markers in the file tell the rest:
    /accumulators/steady_moment_cross came with /steady/a2, a3, and with steady_ci: independent
    /accumulators/steady_ensemble (or any batch subgroup) with the batch subgroups. Where not
    required they are read, and checked, where present."""
    why = reader.why
    s_why = why("dsmc.steady_from")
    out["steady"] = {f"steady/{name}": observable_specs(f"steady/{name}", trail, (), s_why)
                     for name, trail in DSMC_OBSERVABLES}
    sm_why = why("dsmc.steady_from and dsmc.moments > 0")
    out["steady"].update({f"steady/{name}": observable_specs(f"steady/{name}", trail, (), sm_why)
                          for name, trail in moments if name.startswith("moment_")})
    if ("temperature_rotational", ()) in moments:  # rough spheres (dsmc.roughness), one more steady group
        out["steady"]["steady/temperature_rotational"] = observable_specs(
            "steady/temperature_rotational", (), (), why("dsmc.steady_from and dsmc.roughness"))
    acc.append(Spec("accumulators/steady", I8, (DSMC_SCALARS,) + SUMS, True, s_why))
    if P:
        acc.append(Spec("accumulators/moment_steady", I8, (P,) + SUMS, True, s_why))

    estimators = "steady_ci" in section  # written into every resolved config since the estimators exist
    independent = section.get("steady_ci") == "independent"
    every = float(section.get("observe_every") or 0.0)  # 0 with dsmc.observe: rows t > steady_from
    rows = int(np.sum(time > float(section["steady_from"]) + 1e-9 * every))
    levels = block_levels(rows)
    # the batch estimator by the file's ensembles (a shard's own: its intervals cover them only)
    batch_estimator = ("ensembles",) if n >= _STEADY_MIN_ENSEMBLES or levels == 0 else ("blocking",)
    main = ("independent",) if independent else batch_estimator if estimators else \
        ("ensembles", "blocking", "independent")
    e_why = why("dsmc.steady_ci")
    groups = list(out["steady"])
    # independent runs keep the per-ensemble sums, and with them the batch interval, since both exist
    batch = independent and (reader.exists("accumulators/steady_ensemble")
                             or any(reader.exists(f"{g}/batch") for g in groups))
    b_why = why("dsmc.steady_ci: independent")
    for g in groups:
        shape = out["steady"][g][0].shape
        out["intervals"][g] = IntervalSpec(
            g, shape, estimators, main, e_why,
            batch=IntervalSpec(f"{g}/batch", shape, batch, batch_estimator, b_why, ci=True, levels=levels)
            if independent else None, levels=levels)
    if estimators:
        out["text"].append(("steady", "estimator", main, e_why))

    K = DSMC_SCALARS + P
    per_ensemble = estimators and (not independent or batch)
    for name, size in (("steady_ensemble", K), ("steady_blocks", levels * K)):
        if size and (per_ensemble or reader.exists(f"accumulators/{name}")):
            acc.append(Spec(f"accumulators/{name}", I8, (size,) + SUMS, True, e_why))
    pairs = 3 if P >= 3 else 1 if P == 2 else 0
    sonine = bool(pairs) and reader.exists("accumulators/steady_moment_cross")  # both came with /steady/a2
    if sonine:
        acc.append(Spec("accumulators/steady_moment_cross", I8, (pairs,) + SUMS, True, s_why))
    for name, p in (("a2", 2), ("a3", 3)):
        g = f"steady/{name}"
        if P >= p and (sonine or reader.exists(g)):
            a_why = why(f"dsmc.steady_from and dsmc.moments >= {p}")
            out["steady"][g] = [Spec(f"{g}/{key}", F8, (), True, a_why) for key in ("mean", "ci")]
            # from the ensembles' time averages whatever steady_ci says; no tau_int for a ratio
            out["intervals"][g] = IntervalSpec(g, (), sonine, ("ensembles",), a_why, keys=())


def read_interval(reader, spec, n, samples, start):
    """The standard error of a /steady group by its IntervalSpec: {sigma, ci (batch subgroups),
    estimator, tau_int, effective_samples, block_rows, undefined}, or None where the file has
    none and it is not required. With fewer than two ensembles the ensembles estimator has no
    spread to measure: its sigma, ci, tau_int and effective_samples are NaN (undefined), and
    NaN is allowed then only."""
    g, why = spec.group, spec.why
    if not spec.required and not (reader.exists(g) if spec.ci else
                                  reader.exists(f"{g}/sigma") or reader.has_attribute(g, "estimator")):
        return None
    estimator = reader.text(g, "estimator", why)
    if estimator not in spec.estimators:
        reader.fail(f"attribute estimator of /{g}", f"is {estimator!r}, not {' or '.join(spec.estimators)}")
    undefined = estimator == "ensembles" and n < 2
    out = {"estimator": estimator, "undefined": undefined}
    for key in ("sigma", "ci") if spec.ci else ("sigma",):
        out[key] = read_maybe_nan(reader, Spec(f"{g}/{key}", F8, spec.shape, True, why), undefined)
    for key in ("tau_int", "effective_samples"):
        out[key] = reader.number(g, key, why, nan=undefined) if key in spec.keys else None
    got = reader.integer(g, "samples", why, minimum=1)
    if got != samples:
        reader.fail(f"attribute samples of /{g}", f"is {got}, but /steady says {samples}")
    got = reader.number(g, "from", why)
    if got != start:
        reader.fail(f"attribute from of /{g}", f"is {got:g}, but /steady says {start:g}")
    out["block_rows"] = None
    if estimator == "blocking":
        rows = out["block_rows"] = reader.integer(g, "block_rows", why, minimum=1)
        if rows & (rows - 1) or rows >= 1 << spec.levels:
            reader.fail(f"attribute block_rows of /{g}", f"is {rows}, not a power of 2 below {1 << spec.levels}")
    return out


def check_autocorrelation(reader, interval, sigma, variance, samples):
    """RunReadError unless attributes tau_int and effective_samples of an IntervalSpec's group
    are what its sigma, the observable's variance and samples S give (docs/output.md):
    sigma^2 S / (2 variance) and variance / sigma^2 per component, 0.5 and S where either is 0,
    NaN where sigma is; the largest tau_int and the smallest effective_samples of a vector."""
    if "tau_int" not in interval.keys:
        return
    got = {key: reader.number(interval.group, key, interval.why, nan=True) for key in ("tau_int", "effective_samples")}
    tau, neff = [], []
    for s2, v in zip(np.square(np.ravel(sigma).astype(float)), np.ravel(variance).astype(float)):
        if v > 0 and s2 > 0:
            tau.append(s2 * samples / (2 * v))
            neff.append(v / s2)
        else:
            tau.append(0.5 if s2 >= 0 else np.nan)
            neff.append(float(samples) if s2 >= 0 else np.nan)
    want = {"tau_int": np.nan if np.isnan(tau).any() else max(tau),
            "effective_samples": np.nan if np.isnan(neff).any() else min(neff)}
    for key, value in want.items():
        if not (np.isnan(value) and np.isnan(got[key]) or np.isclose(got[key], value, rtol=1e-9, atol=0)):
            reader.fail(f"attribute {key} of /{interval.group}",
                        f"is {got[key]:g}, but sigma, variance and samples give {value:g}")


def read_maybe_nan(reader, spec, nan):
    """reader.dataset(spec), allowing NaN (never an infinity) where `nan`."""
    if not nan:
        return reader.dataset(spec)
    data = reader.dataset(replace(spec, finite=False))
    check_finite(np.nan_to_num(data, nan=0.0, posinf=np.inf, neginf=-np.inf), reader.path, f"dataset /{spec.name}")
    return data


def read_fields(reader, specs, nan=()):
    """{dataset name: array} of the specs of one group; those named in `nan` may hold NaN."""
    return {spec.name.rpartition("/")[2]: read_maybe_nan(reader, spec, spec.name.rpartition("/")[2] in nan)
            for spec in specs}


def read_steady(reader, layout, n):
    """{group: Observable fields} of every /steady group of the layout: mean, ci, variance and,
    where it has an IntervalSpec, sigma, estimator, tau_int, effective_samples, block_rows and
    batch (an Interval, steady_ci: independent). n: the ensembles of the file."""
    if not layout["steady"]:
        return {}
    why = reader.why("dsmc.steady_from")
    reader.group("steady", why)
    samples = reader.integer("steady", "samples", why, minimum=1)
    start = reader.number("steady", "from", why)
    for group, reason in layout["steady_rows"]:
        reader.integer(group, "rows", reason, minimum=1)
    out = {}
    for name, specs in layout["steady"].items():
        spec = layout["intervals"].get(name)
        own = read_interval(reader, spec, n, samples, start) if spec else None
        fields = read_fields(reader, specs, nan=("ci", "bias") if own and own["undefined"] else ())
        fields = {key: fields.get(key) for key in ("mean", "ci", "variance", "bias")}
        batch = read_interval(reader, spec.batch, n, samples, start) if spec and spec.batch else None
        for interval, found in ((spec, own), (spec.batch if spec else None, batch)):
            if found and fields["variance"] is not None:
                check_autocorrelation(reader, interval, found["sigma"], fields["variance"], samples)
        if own:
            fields.update({key: own[key] for key in ("sigma", "estimator", "tau_int", "effective_samples",
                                                     "block_rows")})
        if batch:
            fields["batch"] = Interval(**{key: batch[key] for key in ("sigma", "ci", "estimator", "tau_int",
                                                                       "effective_samples", "block_rows")})
        out[name] = fields
    return out
