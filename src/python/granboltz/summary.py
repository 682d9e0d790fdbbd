"""What repr(run) and str(run) print for a read_run object: a few lines (model, sizes, shard,
time grid, the observables' names and the steady or final values with their confidence
half-widths), never whole arrays, so that a Run in a notebook or a log says what it is."""

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


def summarize(run):
    """The summary of a Run (read_run), one string of a few lines."""
    cfg = run.config
    lines = [f"Run {run.path}"]
    status = "complete" if run.complete else (f"shard {run.shard[0]} of {run.shard[1]} (its means cover only its "
                                              "ensembles: merge the shards)")
    if run.model == "dsmc":
        d = cfg["dsmc"]
        lines.append(f"  dsmc: n = {d['particles']} particles, N = {run.ensembles} ensembles, {status}; "
                     f"λ = {d['kernel']['lambda']:g}, α = {d['alpha']:g}, {d.get('thermostat', 'white_noise')}, "
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
        scalar = _values(run.steady, lambda o: (o.mean, o.ci) if np.ndim(o.mean) == 0 else None)
        lines += _wrap(f"  steady (t > {cfg['dsmc'].get('steady_from', 0):g}):", scalar)
    elif run.model == "dsmc":
        final = _values(run.observables, lambda o: (o.mean[-1], o.ci[-1]) if np.ndim(o.mean) == 1 else None)
        lines += _wrap(f"  at t = {run.time[-1]:g}:", final)
    else:
        scalar = _values(run.observables, lambda o: (o.mean, o.ci) if np.ndim(o.mean) == 0 else None, run.exact)
        lines += _wrap("  results:", scalar)
    return "\n".join(lines)


def observable_summary(obs):
    """One line for an Observable: its name, the shape of its mean, and its value if scalar."""
    if np.ndim(obs.mean) == 0:
        return f"Observable {obs.name} = {format_pm(obs.mean, obs.ci)}"
    return f"Observable {obs.name}: mean and ci of shape {tuple(np.shape(obs.mean))}"
