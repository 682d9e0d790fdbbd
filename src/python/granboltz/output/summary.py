"""What repr(run) and str(run) print for a read_run object: a few lines (model, sizes, shard,
time grid, the observables' names and the steady or final values with their confidence
half-widths; steady ones with their standard error σ, estimator and, for steady_ci:
independent, the batch interval), never whole arrays, so that a Run in a notebook or a log
says what it is."""

import math

import numpy as np

WIDTH = 100  # wrap the lists of values at about this many characters


def format_pm(mean, ci):
    """'mean ± ci' with ci to two significant digits and mean to the same decimal place;
    '(m ± c)e±XX' when the numbers are very small or large, 'mean ± 0' for an exact value."""
    mean, ci = float(mean), float(ci)
    if not (math.isfinite(mean) and math.isfinite(ci)) or ci <= 0:
        return f"{mean:.6g} ± {ci:g}"
    scale = max(abs(mean), ci)
    exponent = math.floor(math.log10(scale)) if scale >= 1e6 or scale < 1e-3 else 0
    m, c = mean / 10.0**exponent, ci / 10.0**exponent
    decimals = max(0, 1 - math.floor(math.log10(c)))
    text = f"{m:.{decimals}f} ± {c:.{decimals}f}"
    return f"({text})e{exponent:+03d}" if exponent else text


def _wrap(head, items, indent="    "):
    lines, line = [], head
    for i, item in enumerate(items):
        piece = item + ("," if i < len(items) - 1 else "")
        if len(line) + 1 + len(piece) > WIDTH and line.strip():
            lines.append(line)
            line = indent + piece
        else:
            line = f"{line} {piece}" if line else piece
    lines.append(line)
    return lines


def _values(observables, pick, exact=None):
    """'name = mean ± ci' of the observables whose pick(Observable) is a scalar pair."""
    out = []
    for name, obs in observables.items():
        pair = pick(obs)
        if pair is None:
            continue
        text = f"{name} = {format_pm(*pair)}"
        if exact is not None and name in exact and np.ndim(exact[name]) == 0:
            text += f" (exact {float(exact[name]):.6g})"
        out.append(text)
    return out


def _estimators(key):
    own, batch = key
    return f"estimator: {own}" + (f", batch: {batch}" if batch else "")


def _format_sigma(sigma):
    """A standard error to two significant digits (as format_pm gives ci)."""
    sigma = float(sigma)
    if not math.isfinite(sigma) or sigma <= 0:
        return f"{sigma:g}"
    if sigma >= 1e6 or sigma < 1e-3:
        return f"{sigma:.1e}"
    return f"{sigma:.{max(0, 1 - math.floor(math.log10(sigma)))}f}"


def _common_estimator(observables):
    """(estimator, batch estimator) most of the steady scalars have, or None for a file without."""
    keys = [(o.estimator, o.batch.estimator if o.batch else None) for o in observables if o.estimator]
    return max(set(keys), key=keys.count) if keys else None


def _steady_value(name, obs, common):
    """'name = mean ± ci (σ sigma[, batch ± ci][; its estimators where they are not the common ones])'."""
    text = f"{name} = {format_pm(obs.mean, obs.ci)}"
    if obs.sigma is None:
        return text
    extra = [f"σ {_format_sigma(obs.sigma)}"]
    if obs.batch is not None:
        extra.append(f"batch ± {_format_sigma(obs.batch.ci)}")
    key = (obs.estimator, obs.batch.estimator if obs.batch else None)
    if key != common:
        extra.append(_estimators(key))
    return f"{text} ({', '.join(extra)})"


def summarize(run):
    """The summary of a Run (read_run), one string of a few lines."""
    cfg = run.config
    lines = [f"Run {run.path}"]
    status = "complete" if run.complete else (f"shard {run.shard[0]} of {run.shard[1]} (its means cover only its "
                                              "ensembles: merge the shards)")
    if run.model == "dsmc":
        d = cfg["dsmc"]
        law = d.get("restitution")
        restitution = (f"α = {d['alpha']:g}" if law is None else f"{law['law']} restitution (" +
                       ", ".join(f"{k} = {v}" for k, v in law.items() if k != "law") + ")")
        lines.append(f"  dsmc: n = {d['particles']} particles, N = {run.ensembles} ensembles, {status}; "
                     f"λ = {d['kernel']['lambda']:g}, {restitution}, {d.get('thermostat', 'white_noise')}, "
                     f"β = {d.get('beta', 0):g}")
        lines.append(f"  t = {run.time[0]:g} … {run.time[-1]:g}, {run.time.size} observation times")
    else:
        m = cfg[run.model]
        about = ", ".join(f"{k} = {m[k]:g}" for k in ("mass", "alpha", "collisions") if k in m)
        bath = m.get("bath", {}).get("kind")
        lines.append(f"  {run.model}: N = {run.ensembles} ensembles, {status}; {about}"
                     + (f", {bath} bath" if bath else ""))
    lines += _wrap("  observables:", list(run.observables))
    if run.steady:
        scalar = {name: o for name, o in run.steady.items() if np.ndim(o.mean) == 0}
        common = _common_estimator(scalar.values())
        head = f"  steady (t > {cfg['dsmc'].get('steady_from', 0):g}"
        if common:
            head += f"; ± ci (σ), {_estimators(common)}"
        lines += _wrap(head + "):", [_steady_value(name, o, common) for name, o in scalar.items()])
    elif run.model == "dsmc":
        final = _values(run.observables, lambda o: (o.mean[-1], o.ci[-1]) if np.ndim(o.mean) == 1 else None)
        lines += _wrap(f"  at t = {run.time[-1]:g}:", final)
    else:
        scalar = _values(run.observables, lambda o: (o.mean, o.ci) if np.ndim(o.mean) == 0 else None, run.exact)
        lines += _wrap("  results:", scalar)
    return "\n".join(lines)


def observable_summary(obs):
    """One line for an Observable: its name, the shape of its mean, and its value if scalar (a
    steady one with sigma and its estimators)."""
    if np.ndim(obs.mean) == 0:
        text = _steady_value(obs.name, obs, None) if obs.sigma is not None else f"{obs.name} = " \
            f"{format_pm(obs.mean, obs.ci)}"
        return f"Observable {text}"
    return f"Observable {obs.name}: mean and ci of shape {tuple(np.shape(obs.mean))}"
