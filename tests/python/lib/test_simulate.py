"""granboltz.simulate and granboltz.Simulation (the extension granboltz._core, built by
`make build`): simulate's output equals the CLI's dataset for dataset, bit for bit; Simulation
advanced in steps, saved and restored, or interrupted by SIGINT gives the same bits as one
uninterrupted advance; its observables are those of its velocities; errors name the key."""

import copy
import os
import re
import signal
import subprocess
import threading
import time

import h5py
import numpy as np
import pytest
import yaml

import granboltz
from conftest import ROOT

BINARY = os.environ.get("GRANBOLTZ_BIN", str(ROOT / "build" / "granboltz"))
BASE = ROOT / "tests" / "bad_inputs" / "base"
C = 0.0795774715459477  # 1/(4 pi)

DSMC = yaml.safe_load((BASE / "dsmc.yaml").read_text())
DSMC["dsmc"].update(histogram={"shells": 8, "radius": 6.0}, steady_from=0.25)


def _with(config, **dsmc):
    out = copy.deepcopy(config)
    out["dsmc"].update(dsmc)
    return out


SWPM = {"model": "dsmc", "seed": 231, "ensembles": 2,
        "dsmc": {"particles": 200, "dimension": 2, "alpha": 0.5, "beta": 1, "gamma": 4,
                 "kernel": {"lambda": 1, "C": 0.15915494309189535}, "t_end": 0.5,
                 "observe_every": 0.25, "histogram": {"shells": 8, "radius": 8, "center": "origin"},
                 "weights": {"method": "swpm", "kappa": 1, "max_particles": 300,
                             "reduction": "energy",
                             "split": {"radius": 3, "rate": 1, "interval": 0.05, "max_radius": 8}}}}
MIXTURE = _with(DSMC, species=[{"name": "heavy", "fraction": 0.25, "mass": 3.0, "diameter": 1.0},
                               {"name": "light", "fraction": 0.75, "mass": 1.0, "diameter": 1.0}],
                kernel={"lambda": 1, "C": C})
ROUGH = _with(DSMC, roughness={"beta": 0.5, "inertia": 0.4}, kernel={"lambda": 1, "C": C})
CONFIGS = {
    "dsmc_global": _with(DSMC, majorant="global"),
    "dsmc_pairwise": _with(DSMC, majorant="pairwise", beta=0, kernel={"lambda": 1, "C": C}),
    "dsmc_strang": _with(DSMC, scheme="strang", steps=8),
    "swpm": SWPM,
    "mixture": MIXTURE,
    "rough": ROUGH,
    "intruder": yaml.safe_load((BASE / "intruder.yaml").read_text()),
    "needle": yaml.safe_load((BASE / "needle.yaml").read_text()),
}


def cli_run(tmp_path, config, name):
    if not os.access(BINARY, os.X_OK):
        pytest.fail(f"{BINARY} is missing: build the simulator first (make build)")
    cfg, out = tmp_path / f"{name}.yaml", tmp_path / f"{name}.h5"
    cfg.write_text(yaml.safe_dump(config))
    subprocess.run([BINARY, "run", str(cfg), "-o", str(out), "-q", "--threads", "1"], check=True)
    return out


def datasets(path):
    out = {}
    with h5py.File(path, "r") as f:
        f.visititems(lambda name, obj: out.__setitem__(name, (obj.dtype.str, obj.shape, obj[()].tobytes()))
                     if isinstance(obj, h5py.Dataset) else None)
    return out


def test_the_extension_is_built():
    # No skip: without granboltz._core (make build) every test here fails, this one saying why.
    import granboltz._core  # noqa: F401

    from granboltz.lib.inprocess import simulate

    assert granboltz.simulate is simulate
    assert issubclass(granboltz.ConfigError, ValueError)


@pytest.mark.parametrize("name", CONFIGS)
def test_simulate_writes_the_clis_datasets_bit_for_bit(tmp_path, name):
    config = CONFIGS[name]
    cli = cli_run(tmp_path, config, "cli")
    out = tmp_path / "py.h5"
    run = granboltz.simulate(config, output=out, threads=2, progress=False)
    assert run.path == str(out)
    a, b = datasets(cli), datasets(out)
    assert a.keys() == b.keys()
    assert [k for k in a if a[k] != b[k]] == []
    assert len(a) > 5


def test_simulate_without_output_returns_a_run_in_memory_and_leaves_no_file(tmp_path, monkeypatch):
    import tempfile

    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    cli = granboltz.read_run(cli_run(tmp_path / "..", DSMC, f"mem_{os.getpid()}"))
    run = granboltz.simulate(DSMC, progress=False)
    assert list(tmp_path.iterdir()) == []  # the temporary file and its directory are gone
    assert np.array_equal(run.temperature.mean, cli.temperature.mean)
    assert np.array_equal(run.temperature.ci, cli.temperature.ci)
    hist = cli.histograms
    for name in hist:  # read before the file went away
        for key, value in hist[name].items():
            assert np.array_equal(run.histograms[name][key], value)


def test_simulate_takes_a_path_and_progress_false_prints_nothing(tmp_path, capfd):
    cfg = tmp_path / "c.yaml"
    cfg.write_text(yaml.safe_dump(DSMC))
    run = granboltz.simulate(cfg, progress=False)
    assert run.model == "dsmc" and run.ensembles == 4
    captured = capfd.readouterr()
    assert captured.out == "" and captured.err == ""
    granboltz.simulate(str(cfg), progress=True)
    # stderr is not a terminal here: no bar redrawn into it, one line when the run ends
    captured = capfd.readouterr()
    assert captured.out == "" and re.fullmatch(r"c\.yaml: 100% in [0-9.e+-]+ s\n", captured.err), captured.err


def test_the_progress_bar_is_drawn_where_stderr_is_a_terminal():
    import io

    from granboltz.lib.progress import ProgressBar

    class Terminal(io.StringIO):
        def isatty(self):
            return True

    term = Terminal()
    bar = ProgressBar("run.yaml", stream=term)
    for k in range(1, 11):
        bar(k / 10)
    bar.close()
    assert "run.yaml: 100%|" in term.getvalue() and "\r" in term.getvalue()  # tqdm redraws in place
    pipe = io.StringIO()
    bar = ProgressBar("run.yaml", stream=pipe)
    bar(0.37)
    bar.close()
    assert pipe.getvalue() == pipe.getvalue().splitlines()[0] + "\n"
    assert pipe.getvalue().startswith("run.yaml: 37% in ")


def test_config_errors_are_the_clis_messages(tmp_path):
    with pytest.raises(granboltz.ConfigError, match=r"dsmc\.alpha = 1\.5: must satisfy 0 < alpha <= 1"):
        granboltz.simulate(_with(DSMC, alpha=1.5), progress=False)
    with pytest.raises(ValueError, match=r"dsmc\.alpha"):
        granboltz.Simulation(_with(DSMC, alpha=1.5))
    with pytest.raises(FileNotFoundError, match="nope.yaml"):
        granboltz.simulate(tmp_path / "nope.yaml", progress=False)
    with pytest.raises(FileNotFoundError, match="nope.h5"):
        granboltz.Simulation.restore(tmp_path / "nope.h5")
    for model in ("intruder", "needle"):
        with pytest.raises(ValueError, match=f"model {model}: only model dsmc"):
            granboltz.Simulation(CONFIGS[model])
    with pytest.raises(ValueError, match="ensemble 4 is not one of"):
        granboltz.Simulation(DSMC, ensemble=4)
    assert list(tmp_path.iterdir()) == []


@pytest.fixture
def sigint_raises():
    """Python's default SIGINT handler for the test's length. A job started in the background
    (CI, nohup) inherits SIGINT ignored, and Python then installs no handler at all."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


def test_simulate_stops_on_sigint_and_leaves_nothing(tmp_path, sigint_raises):
    config = _with(DSMC, particles=20000, gamma=4.0, t_end=400.0, observe_every=0.5)
    config["ensembles"] = 2
    timer = threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        granboltz.simulate(config, output=tmp_path / "out.h5", threads=2, progress=False)
    timer.join()
    assert time.monotonic() - start < 5.0  # promptly, not at the end of the run
    assert list(tmp_path.iterdir()) == []


LONG = _with(DSMC, particles=64, t_end=2.0, observe_every=0.5)
LONG["ensembles"] = 1


STEPPED = ["dsmc_global", "dsmc_pairwise", "dsmc_strang", "swpm", "mixture", "rough"]


def _two_units(name, **dsmc):
    config = copy.deepcopy(CONFIGS[name])
    config["ensembles"] = 1
    config["dsmc"].update(t_end=2.0, observe_every=0.5, **dsmc)
    config["dsmc"].pop("steady_from", None)  # one ensemble: no steady-state interval to read
    return config


@pytest.mark.parametrize("scheme", ["euler", "strang"])
def test_advance_in_steps_equals_one_advance_for_the_splitting_schemes(scheme):
    # The one-species splitting schemes kick and collide on their step grid, wherever advance
    # stops. Not so the no-splitting scheme: an advance discards the waiting time that overshoots
    # t (redrawn from t: exact in law, other bits) and kicks every particle up to t, and the
    # general gas adapts its majorant at every stop; the CLI stops at the observation times, so
    # advancing to those gives its bits (the next test), and a pause (Ctrl-C) is exact.
    config = _two_units("dsmc_global", scheme=scheme, steps=32)
    whole = granboltz.Simulation(config)
    whole.advance(2.0)
    steps = granboltz.Simulation(config)
    for t in (0.5, 1.0, 1.5, 2.0):
        steps.advance(t)
    assert steps.time == whole.time == 2.0
    assert np.array_equal(steps.velocities, whole.velocities)
    assert steps.counts == whole.counts


@pytest.mark.parametrize("name", STEPPED)
def test_advance_to_the_observation_times_gives_the_clis_rows(tmp_path, name):
    # the CLI advances its ensemble to the same times: its one ensemble's temperature row
    config = _two_units(name)
    sim = granboltz.Simulation(config)
    observed = [sim.observe()["temperature"]]
    for t in (0.5, 1.0, 1.5, 2.0):
        sim.advance(t)
        observed.append(sim.observe()["temperature"])
    cli = granboltz.read_run(cli_run(tmp_path, config, name))
    assert np.array_equal(np.array(observed), cli.temperature.mean)


def test_observe_is_the_measure_of_the_velocities():
    sim = granboltz.Simulation(_with(DSMC, moments=4))
    sim.advance(0.5)
    v = sim.velocities
    assert v.shape == (64, 3)
    V = v.mean(axis=0)
    c2 = ((v - V) ** 2).sum(axis=1)
    obs = sim.observe()
    assert obs["density"] == 1.0
    assert np.allclose(obs["bulk_velocity"], V, rtol=0, atol=1e-12)
    assert obs["temperature"] == pytest.approx(c2.mean() / 3, rel=1e-12)
    assert obs["pressure_tensor"].shape == (3, 3)
    for p in range(1, 5):
        assert obs[f"moment_{2 * p}"] == pytest.approx((c2 ** p).mean(), rel=1e-12)
    assert obs["a2"] == pytest.approx(3 / 5 * (c2 ** 2).mean() / c2.mean() ** 2 - 1, rel=1e-10)
    assert "a3" in obs
    assert sim.spins is None and sim.weights is None
    assert set(sim.counts) >= {"collisions", "fictitious", "kicks"}


def test_the_general_gas_and_swpm_members():
    rough = granboltz.Simulation(ROUGH)
    rough.advance(0.25)
    assert rough.spins.shape == (64, 3)
    obs = rough.observe()
    assert obs["T_rot"] > 0
    mix = granboltz.Simulation(MIXTURE).run()
    assert mix.time == 0.5
    obs = mix.observe()
    assert obs["species/heavy/density"] == 0.25 and obs["species/light/density"] == 0.75
    swpm = granboltz.Simulation(SWPM, ensemble=1)
    swpm.advance(0.25)
    assert swpm.velocities.shape[1] == 2
    assert swpm.weights.shape == (len(swpm.velocities),)
    assert swpm.observe()["density"] == pytest.approx(1.0, rel=1e-12)


def test_a_splitting_scheme_refuses_a_time_off_its_grid():
    sim = granboltz.Simulation(CONFIGS["dsmc_strang"])  # dt = 0.5/8
    with pytest.raises(ValueError, match="multiple of dt"):
        sim.advance(0.1)
    sim.advance(0.125)
    with pytest.raises(ValueError, match=">= time"):
        sim.advance(0.0625)


@pytest.mark.parametrize("name", ["dsmc_global", "swpm", "rough"])
def test_save_and_restore_continue_identically(tmp_path, name):
    config = CONFIGS[name]
    sim = granboltz.Simulation(config, ensemble=1)
    sim.advance(0.25)
    sim.save(tmp_path / "state.h5")
    back = granboltz.Simulation.restore(tmp_path / "state.h5")
    assert back.time == 0.25 and back.ensemble == 1 and back.config == sim.config
    assert np.array_equal(back.velocities, sim.velocities)
    sim.advance(0.5)
    back.advance(0.5)
    assert np.array_equal(back.velocities, sim.velocities)
    assert back.counts == sim.counts


# One ensemble long enough (about a second) that a signal sent at 0.3 s arrives while it runs.
INTERRUPTED = _with(DSMC, particles=20000, gamma=4.0, t_end=800.0, observe_every=800.0)
INTERRUPTED["ensembles"] = 1


def test_sigint_pauses_advance_and_a_later_advance_gives_the_same_bits(sigint_raises):
    config = INTERRUPTED
    reference = granboltz.Simulation(config)
    start = time.monotonic()
    reference.run()
    uninterrupted = time.monotonic() - start
    assert uninterrupted > 0.6, "the run is too short to interrupt reliably"

    sim = granboltz.Simulation(config)
    handler = signal.getsignal(signal.SIGINT)
    timer = threading.Timer(0.3, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        sim.run()
    timer.join()
    assert signal.getsignal(signal.SIGINT) is handler  # Python's handler is back
    assert 0.0 < sim.time < 800.0
    sim.run()
    assert np.array_equal(sim.velocities, reference.velocities)
    assert sim.counts == reference.counts


def test_an_ignored_sigint_stays_ignored():
    config = INTERRUPTED
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        sim = granboltz.Simulation(config)
        start = time.monotonic()
        timer = threading.Timer(0.3, os.kill, (os.getpid(), signal.SIGINT))
        timer.start()
        sim.run()  # not paused: the signal was sent while it ran, and is ignored
        timer.join()
        assert time.monotonic() - start > 0.3, "the run ended before the signal was sent"
        assert sim.time == 800.0
        assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN
    finally:
        signal.signal(signal.SIGINT, previous)


def test_the_example_of_docs_python_runs(capsys):
    import re

    text = (ROOT / "docs" / "python.md").read_text()
    section = text[text.index("## Running from Python"):text.index("## Modules")]
    code = re.search(r"^```python\n(.*?)^```$", section, flags=re.M | re.S).group(1)
    exec(compile(code, "docs/python.md", "exec"), {})
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == 5 and lines[-1].startswith("2.0 ")
