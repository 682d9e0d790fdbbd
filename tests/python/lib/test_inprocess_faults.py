"""granboltz.simulate and granboltz.Simulation against misuse: one Simulation from two threads,
an output that is the config, damaged or edited state files, NumPy values and wrong types in
arguments, SIGTERM during simulate. Each ends in a documented exception with a one-line message
or in a correct run, with no file changed or left behind. What could crash or hang the
interpreter runs in a child process."""

import copy
import json
import os
import signal
import subprocess
import sys
import textwrap

import h5py
import numpy as np
import pytest
import yaml

import granboltz
from conftest import ROOT

PYTHONPATH = str(ROOT / "src" / "python")
C = 0.0795774715459477  # 1/(4 pi)

PLAIN = {"model": "dsmc", "seed": 3, "ensembles": 2,
         "dsmc": {"particles": 64, "alpha": 0.5, "beta": 1, "gamma": 4,
                  "kernel": {"lambda": 1, "C": C}, "t_end": 0.5, "observe_every": 0.25}}
SWPM = {"model": "dsmc", "seed": 231, "ensembles": 1,
        "dsmc": {"particles": 200, "dimension": 2, "alpha": 0.5, "beta": 1, "gamma": 4,
                 "kernel": {"lambda": 1, "C": 0.15915494309189535}, "t_end": 0.5,
                 "observe_every": 0.5,
                 "weights": {"method": "swpm", "kappa": 1, "max_particles": 300,
                             "reduction": "energy",
                             "split": {"radius": 3, "rate": 1, "interval": 0.05, "max_radius": 8}}}}
ROUGH = copy.deepcopy(PLAIN)
ROUGH["dsmc"]["roughness"] = {"beta": 0.5, "inertia": 0.4}
MIXTURE = copy.deepcopy(PLAIN)
MIXTURE["dsmc"]["species"] = [{"name": "heavy", "fraction": 0.25, "mass": 3.0, "diameter": 1.0},
                              {"name": "light", "fraction": 0.75, "mass": 1.0, "diameter": 1.0}]
ENGINES = {"plain": PLAIN, "weighted": SWPM, "rough": ROUGH, "mixture": MIXTURE}


def child(code, *args, timeout=60, env=None, cwd=None):
    """Runs `code` in a fresh interpreter with this tree's package: a crash or a hang there is a
    failed test, not the end of pytest."""
    full = dict(os.environ, PYTHONPATH=PYTHONPATH, **(env or {}))
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code), *map(str, args)],
                          capture_output=True, text=True, timeout=timeout, env=full, cwd=cwd)


def one_line(e):
    text = str(e)
    assert "\n" not in text and 0 < len(text) < 1200, text
    return text


# ------------------------------------------------------------------------------------ threads
HAMMER = """
    import json, os, sys, threading
    import numpy as np
    import granboltz
    config, t_end, folder = json.loads(sys.argv[1]), float(sys.argv[2]), sys.argv[3]
    config["dsmc"].update(t_end=t_end, observe_every=t_end)
    sim, reference = granboltz.Simulation(config), granboltz.Simulation(config)
    Busy = getattr(granboltz, "SimulationBusyError", ())
    started, errors = threading.Event(), []
    def advance():
        started.set()
        try:
            sim.advance(t_end)
        except Exception as e:
            errors.append(f"advance: {type(e).__name__}: {e}")
    worker = threading.Thread(target=advance)
    worker.start()
    started.wait()
    members = {
        "velocities": lambda: sim.velocities, "weights": lambda: sim.weights,
        "spins": lambda: sim.spins, "counts": lambda: sim.counts, "time": lambda: sim.time,
        "observe": lambda: sim.observe(), "advance": lambda: sim.advance(t_end),
        "save": lambda: sim.save(os.path.join(folder, "state.h5")), "repr": lambda: repr(sim),
    }
    refused, answered = {}, 0
    while worker.is_alive():
        for name, call in members.items():
            try:
                call()
                answered += 1
            except Busy as e:
                if not str(e).startswith(f"granboltz.Simulation.{name}: refused: another thread "
                                         "is inside advance()") or "\\n" in str(e):
                    errors.append(f"{name}: the message: {e}")
                refused[name] = refused.get(name, 0) + 1
            except Exception as e:
                errors.append(f"{name}: {type(e).__name__}: {e}"[:300])
    worker.join()
    reference.advance(t_end)  # the same engine, never disturbed: the same bits
    print(json.dumps({"refused": refused, "answered": answered, "errors": errors[:5],
                      "same": bool(np.array_equal(sim.velocities, reference.velocities)),
                      "counts": sim.counts == reference.counts, "time": sim.time,
                      "files": sorted(os.listdir(folder))}))
"""


@pytest.mark.parametrize("engine,t_end", [("weighted", 60.0), ("rough", 40.0), ("plain", 200.0)])
def test_one_simulation_used_from_two_threads_refuses_and_is_never_torn(tmp_path, engine, t_end):
    # While one thread is inside advance (GIL released), every call on the same object from
    # another thread raises SimulationBusyError at once; afterwards the state is exactly that of
    # an undisturbed engine. Before the lock: SIGABRT/SIGSEGV within 0.2 s (weighted), garbled
    # states and torn saves (the others).
    config = copy.deepcopy(ENGINES[engine])
    config["ensembles"] = 1
    r = child(HAMMER, json.dumps(config), t_end, tmp_path)
    assert r.returncode == 0, f"exit {r.returncode}: {r.stderr[-2000:]}"
    out = json.loads(r.stdout.strip().splitlines()[-1])
    assert out["errors"] == []
    assert out["same"] and out["counts"] and out["time"] == t_end
    assert set(out["refused"]) >= {"velocities", "counts", "time", "observe", "advance", "save"}
    # a save can only succeed once the advance has returned: never a temporary left
    assert [f for f in out["files"] if f != "state.h5"] == []


def test_two_simulations_in_two_threads_both_run():
    import threading

    config = copy.deepcopy(ROUGH)
    config["dsmc"].update(t_end=20.0, observe_every=20.0)
    a, b = granboltz.Simulation(config, ensemble=0), granboltz.Simulation(config, ensemble=1)
    errors = []

    def run(sim):
        try:
            sim.run()
        except BaseException as e:  # noqa: BLE001 - the test reports it
            errors.append(e)
    threads = [threading.Thread(target=run, args=(s,)) for s in (a, b)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert errors == []
    for sim, e in ((a, 0), (b, 1)):
        alone = granboltz.Simulation(config, ensemble=e).run()
        assert np.array_equal(sim.velocities, alone.velocities) and sim.counts == alone.counts


# ----------------------------------------------------------------- simulate over its config
@pytest.mark.parametrize("spelling", ["same", "dot", "hard link", "symlink"])
def test_simulate_refuses_its_config_as_output(tmp_path, spelling, monkeypatch):
    monkeypatch.chdir(tmp_path)
    cfg = tmp_path / "c.yaml"
    cfg.write_text(yaml.safe_dump(PLAIN))
    before = cfg.read_bytes()
    output = {"same": "c.yaml", "dot": "./c.yaml", "hard link": "h.yaml", "symlink": "l.yaml"}[spelling]
    if spelling == "hard link":
        os.link(cfg, "h.yaml")
    if spelling == "symlink":
        os.symlink("c.yaml", "l.yaml")
    names = sorted(os.listdir(tmp_path))
    with pytest.raises(RuntimeError) as e:
        granboltz.simulate("c.yaml", output=output, progress=False)
    message = one_line(e.value)
    assert output in message and ("same file" in message or "symbolic link" in message)
    assert cfg.read_bytes() == before
    assert sorted(os.listdir(tmp_path)) == names


def test_save_never_replaces_the_config_it_was_made_from(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    cfg = tmp_path / "c.yaml"
    cfg.write_text(yaml.safe_dump(PLAIN))
    os.link(cfg, "h.yaml")
    before = cfg.read_bytes()
    sim = granboltz.Simulation("c.yaml")
    for path in ("c.yaml", "./c.yaml", "h.yaml", b"c.yaml"):
        with pytest.raises(RuntimeError, match="the same file"):
            sim.save(path)
    assert cfg.read_bytes() == before and sorted(os.listdir()) == ["c.yaml", "h.yaml"]
    sim.save("state.h5")  # another file, and a restored one may be saved over its own file
    back = granboltz.Simulation.restore("state.h5")
    back.advance(0.25)
    back.save("state.h5")
    assert granboltz.Simulation.restore("state.h5").time == 0.25


def test_advance_stops_at_t_end_so_that_a_saved_state_restores(tmp_path):
    # Beyond t_end the engines' invariant t <= t_end breaks: such a state was saved but refused
    # by restore ("time outside [0, t_end]"), and advance(1e308) never ended.
    sim = granboltz.Simulation(PLAIN)
    for t in (0.75, 1e308):
        with pytest.raises(ValueError, match=r"<= t_end = 0\.5"):
            sim.advance(t)
    assert sim.time == 0.0
    sim.advance(0.5)
    sim.save(tmp_path / "end.h5")
    assert granboltz.Simulation.restore(tmp_path / "end.h5").time == 0.5


# ------------------------------------------------------------------------- restore's checks
def saved(tmp_path, config, t=0.25, name="state.h5"):
    sim = granboltz.Simulation(config)
    sim.advance(t)
    path = tmp_path / name
    sim.save(path)
    return path


def edited(path, edit):
    with h5py.File(path, "r+") as f:
        edit(f)
    return path


def text_of(value):
    return value.decode() if isinstance(value, bytes) else value


def refused(path, *fragments):
    with pytest.raises(granboltz.RunReadError) as e:
        granboltz.Simulation.restore(path)
    message = one_line(e.value)
    for fragment in fragments:
        assert fragment in message, message
    return message


def test_save_writes_a_digest_and_the_config_hash(tmp_path):
    path = saved(tmp_path, PLAIN)
    with h5py.File(path, "r") as f:
        assert {"kind", "config", "config_hash", "ensemble", "digest"} <= set(f.attrs)
    back = granboltz.Simulation.restore(path)
    assert back.time == 0.25


STREAMS = {"plain": "/state/events_stream", "weighted": "/state/reduce_stream",
           "rough": "/state/sweep_stream", "mixture": "/state/pairs_stream"}


@pytest.mark.parametrize("engine", list(ENGINES))
def test_a_zeroed_random_stream_is_refused_not_a_hang(tmp_path, engine):
    # Before: the all-zero xoshiro state was restored and advance never returned (Ctrl-C did not
    # stop it). Run in a child with a timeout, so that the old hang fails the test.
    path = saved(tmp_path, ENGINES[engine])
    stream = STREAMS[engine]
    edited(path, lambda f: f[stream].__setitem__(slice(None), np.zeros(5, np.uint64)))
    r = child("""
        import sys, granboltz
        try:
            sim = granboltz.Simulation.restore(sys.argv[1])
            sim.advance(sim.t_end)
            print("restored and advanced")
        except granboltz.RunReadError as e:
            print("RunReadError:", e)
    """, path, timeout=30)
    assert r.returncode == 0, r.stderr[-2000:]
    assert r.stdout.startswith("RunReadError:"), r.stdout
    assert f"dataset {stream}" in r.stdout and "all-zero" in r.stdout


def test_particles_reshaped_or_cast_are_refused_naming_the_dataset(tmp_path):
    def reshape(f):
        v = f["/state/particles"][()]
        del f["/state/particles"]
        f["/state/particles"] = v.reshape(-1)

    def cast(f):
        v = f["/state/particles"][()]
        del f["/state/particles"]
        f["/state/particles"] = v.astype(np.int32)

    refused(edited(saved(tmp_path, PLAIN, name="a.h5"), reshape),
            "dataset /state/particles: has shape (256,), not (n, 4)")
    refused(edited(saved(tmp_path, PLAIN, name="b.h5"), cast),
            "dataset /state/particles: has dtype int32, not float64")

    def weighted_cast(f):
        v = f["/state/weighted_particles"][()]
        del f["/state/weighted_particles"]
        f["/state/weighted_particles"] = v.astype(np.float32)
    refused(edited(saved(tmp_path, SWPM, name="c.h5"), weighted_cast),
            "dataset /state/weighted_particles: has dtype float32, not float64")


def test_edits_the_engine_cannot_see_are_refused_by_the_digest(tmp_path):
    path = edited(saved(tmp_path, PLAIN), lambda f: f["/state/particles"].__setitem__((0, 0), 0.125))
    refused(path, "do not match the digest")
    path = edited(saved(tmp_path, PLAIN, name="b.h5"), lambda f: f.attrs.__delitem__("digest"))
    refused(path, "without its digest attribute")
    text = granboltz.Simulation(PLAIN).config  # the config with another alpha
    path = edited(saved(tmp_path, PLAIN, name="c.h5"),
                  lambda f: f.attrs.__setitem__("config", text_of(f.attrs["config"]).replace("alpha: 0.5", "alpha: 0.75")))
    assert text["dsmc"]["alpha"] == 0.5
    refused(path, "attribute config: does not match its config_hash")


def test_restore_of_a_directory_or_a_fifo_says_what_it_is(tmp_path):
    refused(tmp_path, "is a directory")
    fifo = tmp_path / "fifo.h5"
    os.mkfifo(fifo)
    r = child("""
        import sys, granboltz
        try:
            granboltz.Simulation.restore(sys.argv[1])
        except granboltz.RunReadError as e:
            print("RunReadError:", e)
    """, fifo, timeout=30)
    assert "RunReadError:" in r.stdout and "is not a regular file" in r.stdout, r.stdout + r.stderr
    with pytest.raises(FileNotFoundError, match="nope.h5: no such file|'.*nope.h5': no such file"):
        granboltz.Simulation.restore(tmp_path / "nope.h5")
    not_hdf5 = tmp_path / "text.h5"
    not_hdf5.write_text("model: dsmc\n")
    refused(not_hdf5, "text.h5")


# ---------------------------------------------------------------- NumPy values, wrong types
def test_numpy_values_in_a_config_dict_are_the_numbers_they_hold(tmp_path):
    fractions = np.linspace(0.25, 0.75, 2)
    plain = copy.deepcopy(MIXTURE)
    plain["dsmc"]["histogram"] = {"shells": 4, "radius": 5.0, "component": True}
    numpy = copy.deepcopy(plain)
    numpy["seed"] = np.int64(3)
    numpy["dsmc"].update(particles=np.uint32(64), alpha=np.float64(0.5), gamma=np.array(4.0),
                         t_end=np.float32(0.5))
    numpy["dsmc"]["histogram"]["component"] = np.bool_(True)
    numpy["dsmc"]["species"] = tuple({**s, "fraction": f} for s, f in zip(plain["dsmc"]["species"], fractions))
    a = granboltz.simulate(plain, output=tmp_path / "a.h5", progress=False)
    b = granboltz.simulate(numpy, output=tmp_path / "b.h5", progress=False)
    assert a.config == b.config
    assert np.array_equal(a.temperature.mean, b.temperature.mean)
    assert granboltz.Simulation(numpy).config == granboltz.Simulation(plain).config
    # a 1-d array where a number belongs: the simulator's message, not yaml's RepresenterError
    bad = copy.deepcopy(PLAIN)
    bad["dsmc"]["alpha"] = np.linspace(0.1, 0.9, 3)
    with pytest.raises(granboltz.ConfigError, match=r"dsmc\.alpha"):
        granboltz.simulate(bad, progress=False)
    bad["dsmc"]["alpha"] = {1, 2}
    with pytest.raises(granboltz.ConfigError, match=r"dsmc\.alpha = \{1, 2\}: a set is not a config value"):
        granboltz.Simulation(bad)


def test_deep_nesting_is_a_config_error_with_the_readers_limit(tmp_path):
    deep = []
    for _ in range(500):
        deep = [deep]
    config = copy.deepcopy(PLAIN)
    config["dsmc"]["alpha"] = deep
    for call in (lambda: granboltz.simulate(config, progress=False), lambda: granboltz.Simulation(config)):
        with pytest.raises(granboltz.ConfigError) as e:
            call()
        assert f"nested more than {granboltz._core.kMaxConfigDepth} levels" in one_line(e.value)
    looped = copy.deepcopy(PLAIN)
    looped["dsmc"]["kernel"]["self"] = looped["dsmc"]
    with pytest.raises(granboltz.ConfigError, match="nested more than"):
        granboltz.Simulation(looped)
    # the file path meets the C++ reader's own limit with the same number
    cfg = tmp_path / "deep.yaml"
    cfg.write_text("model: dsmc\nx: " + "[" * 500 + "]" * 500 + "\n")
    with pytest.raises(granboltz.ConfigError, match=f"nested more than {granboltz._core.kMaxConfigDepth} levels"):
        granboltz.simulate(cfg, progress=False)


def test_a_config_dict_beyond_the_readers_bounds_is_refused_before_yaml_is_written():
    import time

    config = copy.deepcopy(PLAIN)
    config["dsmc"]["alpha"] = np.zeros(200_000)  # yaml.safe_dump took 21 s, then the reader refused it
    start = time.monotonic()
    with pytest.raises(granboltz.ConfigError, match="a config has at most 100000"):
        granboltz.Simulation(config)
    config["dsmc"]["alpha"] = list(range(150_000))
    with pytest.raises(granboltz.ConfigError, match="more than 100000 values"):
        granboltz.simulate(config, progress=False)
    config["dsmc"]["alpha"] = "x" * 2_000_000
    with pytest.raises(granboltz.ConfigError, match="more than 1048576 bytes"):
        granboltz.Simulation(config)
    assert time.monotonic() - start < 5


def test_counts_out_of_range_or_of_the_wrong_type(tmp_path):
    cases = [
        (lambda: granboltz.simulate(PLAIN, threads=2**70, progress=False), ValueError, r"threads = 1180591620717411303424: .*0 <= threads <= 1024"),
        (lambda: granboltz.simulate(PLAIN, threads=-1, progress=False), ValueError, r"threads = -1: "),
        (lambda: granboltz.simulate(PLAIN, threads=True, progress=False), TypeError, r"threads = True: must be an integer"),
        (lambda: granboltz.simulate(PLAIN, threads=2.0, progress=False), TypeError, r"threads = 2\.0: must be an integer"),
        (lambda: granboltz.Simulation(PLAIN, ensemble=2**64), ValueError, r"ensemble = 18446744073709551616: "),
        (lambda: granboltz.Simulation(PLAIN, ensemble=True), TypeError, r"ensemble = True: must be an integer"),
        (lambda: granboltz.Simulation(PLAIN, ensemble="1"), TypeError, r"ensemble = '1': must be an integer"),
        (lambda: granboltz.Simulation(PLAIN).advance("1"), TypeError, r"must be a real number"),
        (lambda: granboltz.Simulation(PLAIN).advance(True), TypeError, r"must be a real number"),
        (lambda: granboltz.Simulation(PLAIN).advance(10**400), ValueError, r"must be finite"),
        (lambda: granboltz.simulate(PLAIN, output=3, progress=False), TypeError, r"output must be a path"),
        (lambda: granboltz.simulate(PLAIN, output="a\0b.h5", progress=False), ValueError, r"NUL"),
    ]
    for call, kind, pattern in cases:
        with pytest.raises(kind, match=pattern) as e:
            call()
        assert type(e.value) is kind  # not pybind11's TypeError listing the config
        assert len(one_line(e.value)) < 200
    sim = granboltz.Simulation(PLAIN, ensemble=np.int64(1))
    sim.advance(np.float64(0.25))
    assert sim.time == 0.25 and sim.ensemble == 1
    granboltz.simulate(PLAIN, threads=np.int32(1), progress=False)
    assert list(tmp_path.iterdir()) == []


def test_an_engine_larger_than_the_memory_is_refused_before_it_is_allocated():
    # as simulate (run_to_file) refuses such a run; before: std::bad_alloc as MemoryError, or for
    # a size that does fit the address space, the interpreter filled the memory until killed
    huge = copy.deepcopy(PLAIN)
    huge["dsmc"]["particles"] = 10**12
    with pytest.raises(granboltz.ConfigError, match=r"granboltz\.Simulation: the engine needs about .* of memory"):
        granboltz.Simulation(huge)


def test_bytes_and_non_utf8_paths_work_fully(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    run = granboltz.simulate(PLAIN, output=b"o.h5", progress=False)
    assert run.model == "dsmc" and sorted(os.listdir(tmp_path)) == ["o.h5"]
    odd = b"\xff\xfe-run.h5"
    run = granboltz.simulate(PLAIN, output=odd, progress=False)
    assert os.path.exists(odd) and run.ensembles == 2
    cfg = b"\xffconfig.yaml"
    with open(cfg, "w") as f:
        f.write(yaml.safe_dump(PLAIN))
    assert granboltz.Simulation(cfg).ensemble == 0
    sim = granboltz.Simulation(os.fsdecode(cfg)).advance(0.25)
    sim.save(b"\xffstate.h5")
    assert granboltz.Simulation.restore(b"\xffstate.h5").time == 0.25
    with pytest.raises(RuntimeError) as e:  # the message shows the bytes, escaped, on one line
        granboltz.simulate(cfg, output=cfg, progress=False)
    assert "\\xff" in one_line(e.value).lower()


def test_a_config_path_that_is_a_directory_or_a_fifo(tmp_path):
    with pytest.raises(granboltz.ConfigError, match="is a directory, not a config file"):
        granboltz.simulate(tmp_path, progress=False)
    fifo = tmp_path / "c.yaml"
    os.mkfifo(fifo)
    r = child("""
        import sys, granboltz
        try:
            granboltz.Simulation(sys.argv[1])
        except granboltz.ConfigError as e:
            print("ConfigError:", e)
    """, fifo, timeout=30)
    assert "ConfigError:" in r.stdout and "not a regular file" in r.stdout, r.stdout + r.stderr


# ------------------------------------------------------------------------------------ SIGTERM
CHECKPOINTED = {"model": "dsmc", "seed": 5, "ensembles": 3000, "checkpoint": {"every_seconds": 0.05},
                "dsmc": {"particles": 500, "alpha": 0.5, "beta": 1, "kernel": {"lambda": 0, "C": C},
                         "t_end": 4.0, "observe_every": 0.5}}  # about 1 s on one thread
TERMINATED = """
    import os, signal, sys, threading, time, granboltz, yaml
    config, output, mode = yaml.safe_load(open(sys.argv[1])), sys.argv[2], sys.argv[3]
    if mode == "handler":
        def handler(signum, frame):
            raise SystemExit(7)
        signal.signal(signal.SIGTERM, handler)
    def terminate():  # once a first checkpoint exists, else after 0.3 s
        deadline = time.monotonic() + (5 if mode == "checkpoint" else 0.3)
        while time.monotonic() < deadline and not os.path.exists(output + ".checkpoint"):
            time.sleep(0.005)
        os.kill(os.getpid(), signal.SIGTERM)
    threading.Thread(target=terminate, daemon=True).start()
    granboltz.simulate(config, output=None if output.endswith("none.h5") else output, threads=1,
                       progress=False)
    print("the run finished before SIGTERM")
"""


def datasets(path):
    out = {}
    with h5py.File(path, "r") as f:
        f.visititems(lambda name, obj: out.__setitem__(name, obj[()].tobytes())
                     if isinstance(obj, h5py.Dataset) and not name.startswith("provenance") else None)
    return out


def test_sigterm_during_simulate_writes_the_checkpoint_and_dies_of_sigterm(tmp_path):
    cfg = tmp_path / "c.yaml"
    cfg.write_text(yaml.safe_dump(CHECKPOINTED))
    out = tmp_path / "o.h5"
    r = child(TERMINATED, cfg, out, "checkpoint", cwd=tmp_path)
    assert r.returncode == -signal.SIGTERM, (r.returncode, r.stdout, r.stderr[-2000:])
    assert sorted(os.listdir(tmp_path)) == ["c.yaml", "o.h5.checkpoint"]  # no o.h5.tmp.*, no empty checkpoint temporary
    with h5py.File(out.with_name("o.h5.checkpoint"), "r") as f:
        assert text_of(f.attrs["kind"]) == "checkpoint"
        done = f["events/ensemble"].shape[0]
    assert 0 < done < CHECKPOINTED["ensembles"]
    # a later simulate to the same output resumes it: the uninterrupted run's bits
    resumed = granboltz.simulate(cfg, output=out, threads=1, progress=False)
    assert resumed.provenance["resumed_from_checkpoint"] == "yes"
    whole = tmp_path / "whole.h5"
    granboltz.simulate(cfg, output=whole, threads=2, progress=False)
    assert datasets(out) == datasets(whole)
    assert sorted(os.listdir(tmp_path)) == ["c.yaml", "o.h5", "whole.h5"]


@pytest.mark.parametrize("mode", ["no checkpoint", "no output", "handler"])
def test_sigterm_without_a_checkpoint_leaves_nothing(tmp_path, mode):
    config = copy.deepcopy(CHECKPOINTED)
    del config["checkpoint"]
    cfg = tmp_path / "c.yaml"
    cfg.write_text(yaml.safe_dump(config))
    scratch = tmp_path / "tmp"
    scratch.mkdir()
    out = tmp_path / ("none.h5" if mode == "no output" else "o.h5")
    r = child(TERMINATED, cfg, out, "handler" if mode == "handler" else "plain", cwd=tmp_path,
              env={"TMPDIR": str(scratch)})
    # a handler of the user's own is respected (it raised SystemExit(7): the run is cancelled,
    # cleaned up, the exception propagates); else the default: death by SIGTERM
    assert r.returncode == (7 if mode == "handler" else -signal.SIGTERM), (r.returncode, r.stderr[-2000:])
    assert sorted(os.listdir(tmp_path)) == ["c.yaml", "tmp"]
    assert os.listdir(scratch) == []
