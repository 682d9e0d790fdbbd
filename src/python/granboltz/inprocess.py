"""Runs of the simulator in this Python process, through the extension granboltz._core.

    run = granboltz.simulate({"model": "dsmc", ...})       # a whole run, as `granboltz run`
    sim = granboltz.Simulation(config); sim.advance(1.0)   # one DSMC ensemble, step by step

simulate goes through the same C++ (parse_config, run_to_file) as the CLI, so its output file
holds the CLI's datasets bit for bit; Simulation wraps the engine of one ensemble (DsmcEnsemble,
WeightedEnsemble for dsmc.weights, GasEnsemble for mixtures and rough particles). Config errors
raise ConfigError (a ValueError) with the CLI's one-line message, naming the key. See
docs/python.md, "Running from Python".
"""

import os
import pathlib
import shutil
import signal
import sys
import tempfile
import threading

import numpy as np
import yaml

try:
    from . import _core
except ImportError as e:  # pragma: no cover - the message is the point
    raise ImportError(
        "granboltz._core, the simulator's Python extension, is not built: run `make build` "
        f"(needs Debian's pybind11-dev and python3-dev; see docs/python.md) ({e})") from e

ConfigError = _core.ConfigError
ConfigError.__module__ = "granboltz"
ConfigError.__doc__ = ("A config the simulator refuses: the message is the CLI's, naming the key "
                       "(e.g. 'dsmc.alpha = 1.5: must satisfy 0 < alpha <= 1'). A ValueError.")

__all__ = ["simulate", "Simulation", "ConfigError"]


def _config_text(config):
    """(YAML text, origin for messages) of a config dict or a path to a YAML file."""
    if isinstance(config, dict):
        return yaml.safe_dump(config, sort_keys=False), "<config dict>"
    if isinstance(config, (str, os.PathLike)):
        path = pathlib.Path(config)
        if not path.is_file():
            raise FileNotFoundError(f"config file {str(path)!r}: no such file")
        return path.read_text(), str(path)
    raise TypeError(f"config must be a dict or a path to a YAML file, not {type(config).__name__}")


def _sigint_pauses():
    """Whether SIGINT should pause an advance: only where Python itself would raise
    KeyboardInterrupt (the main thread, Python's default handler). An ignored SIGINT (a job
    started in the background or under nohup) stays ignored, and a handler of the user's own
    runs, as Python runs it, once advance returns."""
    return (threading.current_thread() is threading.main_thread()
            and signal.getsignal(signal.SIGINT) is signal.default_int_handler)


class _Bar:
    """A tqdm bar (tqdm.auto: the notebook widget or the terminal) over the run's fraction."""

    def __init__(self, label):
        from tqdm.auto import tqdm

        self._bar = tqdm(total=1000, desc=label, unit="‰", leave=True,
                         bar_format="{desc}: {percentage:3.0f}%|{bar}| [{elapsed}<{remaining}]")
        self._n = 0

    def __call__(self, fraction):
        n = min(1000, max(self._n, int(round(1000 * fraction))))
        if n > self._n:
            self._bar.update(n - self._n)
            self._n = n

    def close(self):
        self._bar.close()


def simulate(config, output=None, threads=None, progress=True):
    """Run a config in-process, as `granboltz run config -o output` does, and return its Run
    (granboltz.read_run).

    config: a dict (dumped to YAML) or a path to a YAML file, validated by the simulator's
    parse_config: a refused config raises ConfigError naming the key, a missing file
    FileNotFoundError. output: the HDF5 file to write; None: a temporary file, read fully into
    memory (histograms included) and removed before returning, so the Run does not depend on any
    file (its .path names the removed file). threads: worker threads (None: the config's
    `threads`, whose default 0 means all cores; never changes results). progress: a tqdm bar
    while it runs; False: nothing is printed.

    The GIL is released while the simulator runs. Ctrl-C (SIGINT) stops the run within about a
    tenth of a second (intruder and needle runs: once their ensembles under way end), removes
    its temporary files and raises KeyboardInterrupt. Python's own setting for SIGINT decides:
    an ignored SIGINT (a background or nohup job) is ignored, and a handler of your own runs
    instead of the stop (the run goes on unless the handler raises).
    """
    from .run import read_run

    text, origin = _config_text(config)
    if threads is not None and (int(threads) != threads or threads < 0):
        raise ValueError(f"threads = {threads!r}: must be an integer >= 0 (0: all cores)")
    _core.normalized_config(text, origin)  # a refused config fails before any file is made
    tmpdir = None
    if output is None:
        tmpdir = tempfile.mkdtemp(prefix="granboltz-simulate-")
        path = os.path.join(tmpdir, "run.h5")
    else:
        path = os.fspath(output)
    bar = _Bar(os.path.basename(origin) if origin != "<config dict>" else "granboltz") if progress else None
    try:
        _core.run_file(text, origin, path, None if threads is None else int(threads), bar,
                       f"granboltz.simulate({origin})")
        if bar is not None:
            bar.close()
            bar = None
        run = read_run(path)
        if tmpdir is not None:
            for name in run.histograms:  # read now: the file goes away
                run.histograms[name]
        return run
    finally:
        if bar is not None:
            bar.close()
        if tmpdir is not None:
            shutil.rmtree(tmpdir, ignore_errors=True)


def _observation(scalars, moments, d, prefix=""):
    out = {}
    for name, offset, rank, _ in _core.kObservables:
        if rank == 0:
            out[prefix + name] = float(scalars[offset])
        elif rank == 1:
            out[prefix + name] = np.array(scalars[offset:offset + 3])
        else:
            out[prefix + name] = np.array(scalars[offset:offset + 9]).reshape(3, 3)
    for p, m in enumerate(moments, start=1):
        out[f"{prefix}moment_{2 * p}"] = float(m)
    if len(moments) >= 2:
        from .sonine import sonine_from_moments

        a2, a3 = sonine_from_moments(moments[0], moments[1], moments[2] if len(moments) >= 3 else None, d)
        out[prefix + "a2"] = float(a2)
        if a3 is not None:
            out[prefix + "a3"] = float(a3)
    return out


class Simulation:
    """One ensemble of a DSMC config (model dsmc only), advanced on request.

    The engine is the one `granboltz run` uses for that ensemble: DsmcEnsemble, WeightedEnsemble
    (dsmc.weights: swpm) or GasEnsemble (dsmc.species or dsmc.roughness), started from the same
    seed and ensemble index, so its velocities at an observation time are those the CLI measures.

    sim.advance(t)   to the absolute time t >= sim.time (splitting schemes: t on the step grid);
                     Ctrl-C stops at a safe point and raises KeyboardInterrupt; the object stays
                     usable, and a later advance gives the same bits as an uninterrupted one
    sim.run()        advance(t_end)
    sim.time, sim.t_end, sim.ensemble, sim.dimension, sim.config (dict), sim.counts (dict)
    sim.velocities   a copy, shape (n, d)
    sim.spins        rough particles: (n, 3) in d = 3, (n,) (the z component) in d = 2; else None
    sim.weights      SWPM: the particle weights, shape (n,); else None
    sim.observe()    the observables now (see its docstring)
    sim.save(path), Simulation.restore(path)   the engine's whole state and the config
    """

    def __init__(self, config, ensemble=0, _core_sim=None):
        if _core_sim is not None:
            self._sim = _core_sim
        else:
            text, origin = _config_text(config)
            if int(ensemble) != ensemble or ensemble < 0:
                raise ValueError(f"ensemble = {ensemble!r}: must be an integer >= 0")
            self._sim = _core.Simulation(text, origin, int(ensemble))
        self._config = yaml.safe_load(self._sim.config_text)

    @classmethod
    def restore(cls, path):
        """The Simulation saved by save(path), to continue exactly where it was."""
        path = os.fspath(path)
        if not os.path.isfile(path):
            raise FileNotFoundError(f"simulation state {path!r}: no such file")
        return cls(None, _core_sim=_core.Simulation.restore(path))

    def save(self, path):
        """Write the engine's state (particles, streams, majorant, counts) and the config to the
        HDF5 file `path` (atomically: a temporary name, renamed when complete)."""
        self._sim.save(os.fspath(path))

    def advance(self, t):
        """Advance to the absolute time t (>= time; for the euler and strang schemes a multiple
        of dt = t_end/steps). The GIL is released meanwhile. Ctrl-C (SIGINT, in the main thread,
        under Python's default handler; an ignored SIGINT stays ignored) stops at the engine's
        next safe point and raises KeyboardInterrupt; time is then where it stopped, and a later
        advance(t) continues exactly as if it had not."""
        if not self._sim.advance(float(t), _sigint_pauses()):
            raise KeyboardInterrupt(f"granboltz.Simulation.advance({t}) interrupted at t = {self.time}")
        return self

    def run(self):
        """advance(t_end)."""
        return self.advance(self.t_end)

    @property
    def time(self):
        return self._sim.time

    @property
    def t_end(self):
        return self._sim.t_end

    @property
    def ensemble(self):
        return self._sim.ensemble

    @property
    def dimension(self):
        return self._sim.dimension

    @property
    def config(self):
        """The config with every default explicit (as `granboltz validate` prints it)."""
        return self._config

    @property
    def velocities(self):
        return self._sim.velocities

    @property
    def spins(self):
        return self._sim.spins

    @property
    def weights(self):
        return self._sim.weights

    @property
    def counts(self):
        """{collisions, fictitious, kicks} so far (SWPM also reductions, split_sweeps)."""
        return self._sim.counts

    def observe(self):
        """The observables now, as the simulator measures them at an observation time:
        every name of the output's observables (density, bulk_velocity [3], temperature,
        pressure_tensor [3, 3], heat_flux [3], fourth_moment, crit, temperature_uncentred),
        moment_2 .. moment_2P (P = dsmc.moments) and a2 (P >= 2), a3 (P >= 3) from them. The
        general gas adds each species' as "species/<name>/<observable>" and, rough, "T_rot"."""
        raw = self._sim.observe()
        d = self.dimension
        out = _observation(raw["scalars"], raw["moments"], d)
        for group, scalars, moments in raw["rows"]:
            prefix = group.strip("/") + "/"
            if len(scalars) == 1:  # T_rot
                out[group.strip("/").rpartition("/")[2] or "T_rot"] = float(scalars[0])
            else:
                out.update(_observation(scalars, moments, d, prefix))
        return out

    def __repr__(self):
        return (f"granboltz.Simulation(engine={self._sim.engine}, ensemble={self.ensemble}, "
                f"n={len(self.velocities)}, d={self.dimension}, time={self.time!r}, "
                f"t_end={self.t_end!r})")
