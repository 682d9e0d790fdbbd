"""Runs of the simulator in this Python process, through the extension granboltz._core.

    run = granboltz.simulate({"model": "dsmc", ...})       # a whole run, as `granboltz run`
    sim = granboltz.Simulation(config); sim.advance(1.0)   # one DSMC ensemble, step by step

simulate goes through the same C++ (parse_config, run_to_file) as the CLI, so its output file
holds the CLI's datasets bit for bit; Simulation wraps the engine of one ensemble (DsmcEnsemble,
WeightedEnsemble for dsmc.weights, GasEnsemble for mixtures and rough particles). Config errors
raise ConfigError (a ValueError) with the CLI's one-line message, naming the key. See
docs/python.md, "Running from Python".
"""

import numbers
import os
import shutil
import stat
import sys
import tempfile

import numpy as np
import yaml

try:
    from .. import _core
except ImportError as e:  # pragma: no cover - the message is the point
    raise ImportError(
        "granboltz._core, the simulator's Python extension, is not built: run `make build` "
        f"(needs Debian's pybind11-dev and python3-dev; see docs/python.md) ({e})") from e

from ..output.io import RunReadError

ConfigError = _core.ConfigError
ConfigError.__module__ = "granboltz"
ConfigError.__doc__ = ("A config the simulator refuses: the message is the CLI's, naming the key "
                       "(e.g. 'dsmc.alpha = 1.5: must satisfy 0 < alpha <= 1'). A ValueError.")
SimulationBusyError = _core.SimulationBusyError
SimulationBusyError.__module__ = "granboltz"
SimulationBusyError.__doc__ = (
    "A call on a granboltz.Simulation while another thread is inside one of its calls (advance "
    "releases the GIL): refused at once, nothing is changed. One Simulation is used by one thread "
    "at a time; give each thread its own. A RuntimeError.")

__all__ = ["simulate", "Simulation", "ConfigError", "SimulationBusyError"]

from .arguments import MAX_THREADS, config_text, integer_argument, path_argument, real_array, shorten  # noqa: E402
from .progress import ProgressBar, sigint_pauses  # noqa: E402


def simulate(config, output=None, threads=None, progress=True):
    """Run a config in-process, as `granboltz run config -o output` does, and return its Run
    (granboltz.read_run).

    config: a dict (dumped to YAML; NumPy scalars and arrays as the numbers and lists they hold)
    or a path to a YAML file, validated by the simulator's parse_config: a refused config raises
    ConfigError naming the key, a missing file FileNotFoundError. output: the HDF5 file to write
    (str, bytes or os.PathLike; never the config file itself, a link, a directory or a FIFO:
    RuntimeError before anything is written); None: a temporary file, read fully into memory
    (histograms included) and removed before returning, so the Run does not depend on any file
    (its .path names the removed file). threads: worker threads, an integer 0..1024 (None: the
    config's `threads`, whose default 0 means all cores; never changes results). progress: a
    tqdm bar while it runs in a terminal or a notebook; where stderr is neither (a script's log,
    a pipe) one line when it ends ("c.yaml: 100% in 2.1 s"); False: nothing is printed.

    The GIL is released while the simulator runs. Ctrl-C (SIGINT) stops the run within about a
    tenth of a second (intruder and needle runs: once their ensembles under way end), removes
    its temporary files and raises KeyboardInterrupt. Python's own setting for SIGINT decides:
    an ignored SIGINT (a background or nohup job) is ignored, and a handler of your own runs
    instead of the stop (the run goes on unless the handler raises). SIGTERM under Python's
    default (the process would die of it) ends the process as `granboltz run` does: a config
    with `checkpoint` writes a last checkpoint, the run stops and its temporary files go, and
    the process then dies of SIGTERM; a handler of your own or an ignored SIGTERM is respected
    as for SIGINT.
    """
    from ..output.run import read_run

    text, origin, config_path = config_text(config)
    if threads is not None:
        threads = integer_argument("threads", threads, 0, MAX_THREADS, f"0 <= threads <= {MAX_THREADS} (0: all cores)")
    if output is not None:
        output, output_raw = path_argument(output, "output")
    _core.normalized_config(text, origin)  # a refused config fails before any file is made
    tmpdir = None
    if output is None:
        tmpdir = tempfile.mkdtemp(prefix="granboltz-simulate-")
        output = os.path.join(tmpdir, "run.h5")
        output_raw = os.fsencode(output)
    shown = os.fsdecode(origin)
    bar = ProgressBar(os.path.basename(shown) if config_path else "granboltz") if progress else None
    terminated = False
    try:
        terminated = _core.run_file(text, origin, config_path, output_raw, threads, bar,
                                    f"granboltz.simulate({shown})".encode("utf-8", "backslashreplace"))
        if terminated:
            return None  # the finally clause cleans up and ends the process
        if bar is not None:
            bar.close()
            bar = None
        run = read_run(output)
        if tmpdir is not None:
            for name in run.histograms:  # read now: the file goes away
                run.histograms[name]
        return run
    finally:
        if bar is not None:
            bar.close()
        if tmpdir is not None:
            shutil.rmtree(tmpdir, ignore_errors=True)
        if terminated:
            # SIGTERM under its default disposition: the run stopped (a checkpoint, if the
            # config has one, is written); the process now ends as the signal asked.
            sys.stderr.flush()
            _core.end_by_sigterm()


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
        from ..theory.sonine import sonine_from_moments

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
                     usable, and a later advance gives the same bits as an uninterrupted one.
                     The GIL is released: a call on the same object from another thread
                     meanwhile raises SimulationBusyError (one Simulation, one thread at a time)
    sim.run()        advance(t_end)
    sim.time, sim.t_end, sim.ensemble, sim.dimension, sim.config (dict), sim.counts (dict)
    sim.velocities   a copy, shape (n, d)
    sim.spins        rough particles: (n, 3) in d = 3, (n,) (the z component) in d = 2; else None
    sim.weights      SWPM: the particle weights, shape (n,); else None
    sim.observe()    the observables now (see its docstring)
    sim.set_velocities(v), sim.set_spins(w)   replace the state now (checked; see their docstrings)
    sim.save(path), Simulation.restore(path)   the engine's whole state and the config
    """

    def __init__(self, config, ensemble=0, _core_sim=None):
        self._config_file = b""  # the config's file, which save() never replaces
        if _core_sim is not None:
            self._sim = _core_sim
        else:
            text, origin, self._config_file = config_text(config)
            ensemble = integer_argument("ensemble", ensemble, 0, 2**64 - 1,
                                "0 <= ensemble < the config's ensembles")
            self._sim = _core.Simulation(text, origin, ensemble)
        self._config = yaml.safe_load(self._sim.config_text)

    @classmethod
    def restore(cls, path):
        """The Simulation saved by save(path), to continue exactly where it was. The file is
        checked as a checkpoint is: a missing file raises FileNotFoundError; anything else that
        is not a state saved by this granboltz — a directory, a FIFO, not HDF5, damaged, edited
        (its datasets against the digest save() wrote, its config against its hash), a dataset
        of the wrong shape or dtype, a random stream in the all-zero state, a state without a
        digest (older versions) — raises granboltz.RunReadError naming the file and, where one
        is to blame, the dataset."""
        shown, raw = path_argument(path, "simulation state")
        try:  # before opening: a FIFO would block, and HDF5 would call a directory "no such file"
            mode = os.stat(raw).st_mode
        except FileNotFoundError:
            raise FileNotFoundError(f"simulation state {shown!r}: no such file") from None
        except OSError as e:
            raise RunReadError(shown, "the file", f"cannot open it ({e.strerror})") from None
        if stat.S_ISDIR(mode):
            raise RunReadError(shown, "the file", "is a directory, not a simulation state")
        if not stat.S_ISREG(mode):
            raise RunReadError(shown, "the file", "is not a regular file (a FIFO or a device?), "
                                                  "not a simulation state")
        try:
            core = _core.Simulation.restore(raw)
        except _core.StateError as e:
            message = str(e)
            problem = message.split(": ", 1)[1] if message.startswith(shown + ": ") else message
            raise RunReadError(shown, "the file", problem, message=message) from None
        return cls(None, _core_sim=core)

    def save(self, path):
        """Write the engine's state (particles, streams, majorant, counts), the config with its
        hash and a digest of the datasets to the HDF5 file `path` (atomically: a temporary name,
        renamed when complete; never through a link, over a directory, a FIFO or the config file
        this Simulation was made from: RuntimeError naming the path)."""
        self._sim.save(path_argument(path, "save path")[1], self._config_file)

    def advance(self, t):
        """Advance to the absolute time t (a real number, time <= t <= t_end; for the euler and
        strang schemes a multiple of dt = t_end/steps). The GIL is released meanwhile, and any other
        call on this object from another thread raises SimulationBusyError until advance
        returns. Ctrl-C (SIGINT, in the main thread, under Python's default handler; an ignored
        SIGINT stays ignored) stops at the engine's next safe point and raises
        KeyboardInterrupt; time is then where it stopped, and a later advance(t) continues
        exactly as if it had not."""
        if isinstance(t, (bool, np.bool_)) or not isinstance(t, numbers.Real):
            raise TypeError(f"advance(t): t = {shorten(t)}: must be a real number (a time), "
                            f"not a {type(t).__name__}")
        try:
            value = float(t)
        except OverflowError:
            raise ValueError(f"advance({shorten(t, 40)}): t must be finite and >= time") from None
        if not self._sim.advance(value, sigint_pauses()):
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

    def set_velocities(self, velocities):
        """Replace every velocity now: real numbers, shape (n, d), finite, |v| <= 1e150, else a
        one-line ValueError/TypeError and nothing changed (docs/python.md)."""
        self._sim.set_velocities(real_array("set_velocities", "velocities", velocities, (None, self.dimension)))
        return self

    def set_spins(self, spins):
        """Rough particles: every spin now, shape (n, 3) in d = 3, (n,) in d = 2, as set_velocities."""
        self._sim.set_spins(real_array("set_spins", "spins", spins, (None, 3) if self.dimension == 3 else (None,)))
        return self

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
        head = f"granboltz.Simulation(engine={self._sim.engine}, ensemble={self.ensemble}, "
        try:
            n, time = self._sim.particle_count, self.time
        except SimulationBusyError:
            return head + f"d={self.dimension}, busy in another thread, t_end={self.t_end!r})"
        return head + f"n={n}, d={self.dimension}, time={time!r}, t_end={self.t_end!r})"
