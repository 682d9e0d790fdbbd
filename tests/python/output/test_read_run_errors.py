"""granboltz.read_run (and the readers of granboltz.output.io) on files that are not complete outputs:
every failure is RunReadError naming the file and the dataset or attribute, never a bare
KeyError, RuntimeError or OSError of h5py.

A seeded corruption campaign over outputs of the three models made by the simulator (DSMC twice:
steady_ci batch, and independent with its batch subgroups and the component histogram; byte
flips, truncations, h5py edits of datasets and attributes, garbage configs): each damaged file
either reads with every value equal to the original's (a flip in bytes HDF5 does not use) or
raises RunReadError. Plus checkpoints, foreign HDF5 files, a shard without /events/kicks, damaged
steady intervals and component histograms, files of older simulators, a text file, an empty
file, a directory and a missing path."""

import contextlib
import os
import pickle
import shutil
import signal
import subprocess
import time

import h5py
import numpy as np
import pytest
import yaml

import granboltz
from granboltz.output.io import RunReadError, open_run, provenance, read_config, read_dataset, read_finite
from granboltz.output.run import LazyHistograms, read_run
from conftest import BASE, BINARY, run_binary

# The base configs with every optional part a model can write: histograms, steady state, exact values.
DSMC = ["--set", "dsmc.histogram.shells=8", "--set", "dsmc.histogram.radius=5", "--set", "dsmc.steady_from=0.2"]
SETTINGS = {
    "dsmc": DSMC,
    # the papers' steady interval with the batch one beside it, and the histogram of (v - V)_x
    "dsmc_independent": DSMC + ["--set", "dsmc.steady_ci=independent", "--set", "dsmc.histogram.component=true",
                                "--set", "dsmc.t_end=1", "--set", "dsmc.moments=2"],
    "intruder": ["--set", "intruder.histogram.bins=6", "--set", "intruder.histogram.range=3"],
    "needle": ["--set", "needle.alpha=1", "--set", "needle.velocity_histogram.bins=6",
               "--set", "needle.velocity_histogram.range=3", "--set", "needle.omega_histogram.bins=5",
               "--set", "needle.omega_histogram.range=3"],
}
FLIPS, TRUNCATIONS, EDITS = 22, 6, 22  # per output: 200 cases in all


@pytest.fixture(scope="session")
def outputs(tmp_path_factory):
    """{model: path} of a small output of each model, and "shard": shard 0 of 2 of a DSMC run."""
    d = tmp_path_factory.mktemp("outputs")
    paths = {}
    for model, extra in SETTINGS.items():
        paths[model] = d / f"{model}.h5"
        run_binary("run", BASE / f"{model.partition('_')[0]}.yaml", "-q", "--threads", "1", "-o", paths[model],
                   *extra)
    paths["shard"] = d / "shard.h5"
    run_binary("run", BASE / "dsmc.yaml", "-q", "--threads", "1", "-o", paths["shard"],
               "--set", "shard.index=0", "--set", "shard.count=2")
    return paths


def snapshot(path):
    """Everything read_run gives for `path`, histograms included, as plain nested values."""
    run = read_run(path)

    def obs(o):
        return {"name": o.name, "mean": o.mean, "ci": o.ci, "variance": o.variance, "per_ensemble": o.per_ensemble,
                "sigma": o.sigma, "estimator": o.estimator, "tau_int": o.tau_int,
                "effective_samples": o.effective_samples, "block_rows": o.block_rows,
                "batch": None if o.batch is None else vars(o.batch)}

    return {"model": run.model, "config": run.config, "ensembles": run.ensembles, "time": run.time,
            "observables": {k: obs(v) for k, v in run.observables.items()},
            "steady": {k: obs(v) for k, v in run.steady.items()},
            "events": dict(run.events), "exact": dict(run.exact), "provenance": dict(run.provenance),
            "histograms": {k: dict(v) for k, v in run.histograms.items()},
            "shard": run.shard, "complete": run.complete}


def same(a, b):
    if isinstance(a, dict):
        return isinstance(b, dict) and a.keys() == b.keys() and all(same(a[k], b[k]) for k in a)
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        a, b = np.asarray(a), np.asarray(b)
        return a.shape == b.shape and a.dtype == b.dtype and np.array_equal(a, b, equal_nan=a.dtype.kind == "f")
    return type(a) is type(b) and a == b


# ----------------------------------------------------------------------------- the campaign
def datasets_of(path):
    names = []
    with h5py.File(path, "r") as f:
        f.visititems(lambda name, obj: names.append(name) if isinstance(obj, h5py.Dataset) else None)
    return sorted(names)


def replace_dataset(f, name, data):
    del f[name]
    f.create_dataset(name, data=data)


def required_attributes(path):
    """(owner, key) of the attributes read_run requires in this file."""
    with h5py.File(path, "r") as f:
        out = [("/", k) for k in ("config", "model", "seed", "ensembles", "version", "git_sha",
                                  "confidence_lambda_p")]
        out.append(("provenance", "shard"))
        owners = [("steady", ("samples", "from", "estimator")), ("steady/histogram", ("rows",)),
                  ("steady/histogram_component", ("rows",)), ("histogram", ("samples", "center")),
                  ("histogram_component", ("center",)), ("velocity_histogram", ("samples",)),
                  ("omega_histogram", ("samples",)), ("accumulators", tuple(f["accumulators"].attrs))]
        # the steady intervals' attributes (block_rows, one power of 2 for another, cannot be told)
        interval = ("estimator", "tau_int", "effective_samples", "samples", "from")
        for name in f["steady"] if "steady" in f else ():
            owners += [(f"steady/{name}", interval), (f"steady/{name}/batch", interval)]
        for owner, keys in owners:
            if owner in f:
                out += [(owner, k) for k in keys if k in f[owner].attrs]
    return out


GARBAGE_CONFIGS = [b"model: dsmc\n  seed: [1, 2\n", b"- just\n- a list\n", b"seed: 1\nensembles: 4\n",
                   b"model: boltzmann\nensembles: 4\n", b"\xff\xfe not utf-8", b"", b"model: dsmc\nensembles: 4\n",
                   np.arange(3)]


def edit_cases(path, rng, count):
    """`count` seeded h5py edits of the output `path`: (label, function of an open h5py.File)."""
    names = datasets_of(path)
    attrs = required_attributes(path)
    cases = []

    def pick(values):  # a Python value (rng.choice would make NumPy strings, which h5py refuses)
        return values[int(rng.integers(len(values)))]

    def delete_dataset():
        name = str(rng.choice(names))
        return f"delete /{name}", lambda f: f.__delitem__(name)

    def reshape_dataset():
        name = str(rng.choice(names))

        def edit(f):
            data = f[name][()]
            replace_dataset(f, name, np.append(np.ravel(data), np.ravel(data)[:1]) if np.ndim(data) <= 1
                            else data[:-1] if data.shape[0] > 1 else np.concatenate([data, data]))
        return f"reshape /{name}", edit

    def retype_dataset():
        name = str(rng.choice(names))
        to = {"f": np.float32, "u": np.int64, "i": np.uint64}

        def edit(f):
            data = f[name][()]
            replace_dataset(f, name, np.asarray(data).astype(to[np.asarray(data).dtype.kind]))
        return f"retype /{name}", edit

    def non_finite():
        # any dataset read_run reads (the accumulators are checked for shape and dtype only)
        name = str(rng.choice([n for n in names if not n.startswith("accumulators/")]))

        def edit(f):
            data = np.array(f[name][()])
            if data.dtype.kind != "f":
                data = data.astype(np.float64)  # a counter as double: wrong dtype, refused as well
            data.flat[rng.integers(data.size)] = pick([np.nan, np.inf, -np.inf])
            replace_dataset(f, name, data)
        return f"non-finite in /{name}", edit

    def delete_attribute():
        owner, key = attrs[rng.integers(len(attrs))]
        return f"delete attribute {key} of {owner}", lambda f: f[owner].attrs.__delitem__(key)

    def alter_attribute():
        owner, key = attrs[rng.integers(len(attrs))]

        def edit(f):
            value = f[owner].attrs[key]
            if key == "config":
                f.attrs["config"] = yaml.safe_dump(dict(yaml.safe_load(value), seed=12345))
            elif key == "shard":
                f[owner].attrs[key] = pick(["2/2", "x/2", "0", "1/0", "-1/2"])
            elif key == "model":
                f.attrs[key] = {"dsmc": "needle"}.get(value.decode(), "dsmc")
            elif key in ("estimator", "center"):  # another valid value, or text as a number
                f[owner].attrs[key] = pick({"estimator": ["independent", "ensembles", "blocking", 7],
                                            "center": ["bulk", "origin", 7]}[key])
            elif isinstance(value, (bytes, str)):
                f[owner].attrs[key] = 7  # text as a number
            elif key == "confidence_lambda_p":
                f.attrs[key] = pick([-3.2, np.nan, "3.2"])
            else:
                f[owner].attrs[key] = pick([value + 1, -1, "four", 0.5]) if key != "from" else "soon"
        return f"alter attribute {key} of {owner}", edit

    def garbage_config():
        value = GARBAGE_CONFIGS[rng.integers(len(GARBAGE_CONFIGS))]

        def edit(f):
            f.attrs["config"] = value
        return f"config {value!r:.30}", edit

    def events_out_of_order():
        return "reorder /events/ensemble", lambda f: replace_dataset(f, "events/ensemble",
                                                                     f["events/ensemble"][()][::-1])

    kinds = [delete_dataset, reshape_dataset, retype_dataset, non_finite, delete_attribute, alter_attribute,
             garbage_config, events_out_of_order]
    for i in range(count):
        cases.append(kinds[i % len(kinds)]() if i < len(kinds) else kinds[rng.integers(len(kinds))]())
    return cases


def campaign(outputs, directory, seed=20240611):
    """[(label, path of the damaged copy, original path)] of the whole campaign."""
    rng = np.random.default_rng(seed)
    cases = []
    for model in SETTINGS:
        original = outputs[model]
        data = original.read_bytes()
        for i in range(FLIPS):
            at = int(rng.integers(len(data)))
            damaged = bytearray(data)
            damaged[at] ^= int(rng.integers(1, 256))
            path = directory / f"{model}-flip{i}.h5"
            path.write_bytes(bytes(damaged))
            cases.append((f"{model}: flip byte {at}", path, original))
        for i in range(TRUNCATIONS):
            size = int(rng.integers(len(data)))
            path = directory / f"{model}-cut{i}.h5"
            path.write_bytes(data[:size])
            cases.append((f"{model}: truncate to {size} of {len(data)} bytes", path, original))
        for i, (label, edit) in enumerate(edit_cases(original, rng, EDITS)):
            path = directory / f"{model}-edit{i}.h5"
            shutil.copyfile(original, path)
            with h5py.File(path, "a") as f:
                edit(f)
            cases.append((f"{model}: {label}", path, original))
    return cases


def outcome(path, expected):
    """"read" (every value equal to the original's), "RunReadError", or what went wrong."""
    try:
        got = snapshot(path)
    except RunReadError as err:
        assert err.path == str(path) and str(path) in str(err) and err.name, err
        return "RunReadError"
    except Exception as err:  # noqa: BLE001 - what the campaign is looking for
        return f"{type(err).__name__}: {err}"
    return "read" if same(got, expected) else "read, with values that differ from the original"


def test_corrupted_outputs_read_unchanged_or_raise_run_read_error(outputs, tmp_path):
    start = time.monotonic()
    expected = {path: snapshot(path) for path in (outputs[m] for m in SETTINGS)}
    cases = campaign(outputs, tmp_path)
    results = [(label, outcome(path, expected[original])) for label, path, original in cases]
    tally = {}
    for _, result in results:
        key = result if result in ("read", "RunReadError") else "other"
        tally[key] = tally.get(key, 0) + 1
    bad = [f"{label}: {result}" for label, result in results if result not in ("read", "RunReadError")]
    assert not bad, f"{len(bad)} of {len(results)} cases ({tally}):\n" + "\n".join(bad)
    assert len(results) == 50 * len(SETTINGS) and tally.get("RunReadError", 0) > 130
    assert time.monotonic() - start < 30


# ----------------------------------------------------------------------------- explicit cases
def expect_error(path, *patterns):
    with pytest.raises(RunReadError) as err:
        read_run(path)
    for pattern in patterns:
        assert pattern in str(err.value), str(err.value)
    assert err.value.path == str(path)
    return err.value


def make_checkpoint(tmp_path):
    """A real checkpoint: a run long enough to be stopped by SIGTERM after its first checkpoint."""
    out = tmp_path / "long.h5"
    if not os.access(BINARY, os.X_OK):
        pytest.fail(f"{BINARY} is missing: build the simulator first (make build)")
    # Checkpoints 50 ms apart: a SIGTERM that arrives while one is being written is lost (the
    # driver clears the request after the write), so it is sent again until the run stops.
    proc = subprocess.Popen([BINARY, "run", str(BASE / "dsmc.yaml"), "-q", "--threads", "1", "-o", str(out),
                             "--set", "ensembles=4000", "--set", "dsmc.particles=2000", "--set", "dsmc.t_end=2",
                             "--set", "checkpoint.every_seconds=0.05"], stderr=subprocess.DEVNULL)
    checkpoint = tmp_path / "long.h5.checkpoint"
    try:
        deadline = time.monotonic() + 60
        while not checkpoint.exists() and proc.poll() is None and time.monotonic() < deadline:
            time.sleep(0.005)
        while proc.poll() is None and time.monotonic() < deadline:
            proc.send_signal(signal.SIGTERM)
            with contextlib.suppress(subprocess.TimeoutExpired):
                proc.wait(timeout=0.5)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert checkpoint.exists() and not out.exists(), f"exit {proc.returncode}: no checkpoint left"
    return checkpoint


def test_a_checkpoint_is_named_as_one(tmp_path):
    checkpoint = make_checkpoint(tmp_path)
    err = expect_error(checkpoint,
                       "is a checkpoint of an unfinished run, not an output; resume the run with granboltz run")
    assert err.name == "the file"
    with pytest.raises(RunReadError, match="is a checkpoint"):
        with open_run(checkpoint):
            pass


def test_a_checkpoint_is_recognised_by_its_attributes(tmp_path):
    # as run.cpp write_checkpoint writes it: the record, then config, shard_index/count, saved_utc
    path = tmp_path / "out.h5.checkpoint"
    with h5py.File(path, "w") as f:
        f.attrs["config"] = (BASE / "dsmc.yaml").read_text()
        f.attrs["shard_index"], f.attrs["shard_count"] = np.uint64(0), np.uint64(1)
        f.attrs["saved_utc"] = "2024-01-01T00:00:00Z"
        f["events/ensemble"] = np.arange(2, dtype=np.uint64)
        f.create_group("accumulators")
    expect_error(path, "is a checkpoint of an unfinished run")


def test_a_foreign_hdf5_file_is_not_a_granboltz_output(tmp_path):
    path = tmp_path / "foreign.h5"
    with h5py.File(path, "w") as f:
        f["ensembles"] = np.arange(4)
        f["strings"] = np.array([b"a", b"b"])
        f.attrs["model"] = "dsmc"
    err = expect_error(path, "foreign.h5: not a granboltz output (no /config attribute)")
    assert err.name == "attribute config"
    with h5py.File(path, "r") as f:
        with pytest.raises(RunReadError, match="no /config attribute"):
            read_config(f)
        with pytest.raises(RunReadError, match=r"dataset /time: missing"):
            read_dataset(f, "time")
        with pytest.raises(RunReadError, match=r"dataset /strings: is not numeric"):
            read_finite(f, "strings")


def test_a_shard_reads_but_must_have_every_dataset(outputs, tmp_path):
    run = read_run(outputs["shard"])
    assert run.shard == (0, 2) and not run.complete and run.events["kicks"].shape == (2,)
    path = tmp_path / "shard.h5"
    shutil.copyfile(outputs["shard"], path)
    with h5py.File(path, "a") as f:
        del f["events/kicks"]
    err = expect_error(path, "shard.h5: dataset /events/kicks: missing (every dsmc output has it)")
    assert err.name == "dataset /events/kicks"


def test_a_text_file_an_empty_file_a_directory_and_a_missing_path(tmp_path):
    (tmp_path / "text.h5").write_text("model: dsmc\n")
    (tmp_path / "empty.h5").write_bytes(b"")
    (tmp_path / "dir.h5").mkdir()
    expect_error(tmp_path / "text.h5", "text.h5: cannot read the file")
    expect_error(tmp_path / "empty.h5", "empty.h5: cannot read the file")
    expect_error(tmp_path / "dir.h5", "dir.h5: is a directory")
    expect_error(tmp_path / "missing.h5", "missing.h5: no such file")
    for name in ("text.h5", "empty.h5", "dir.h5", "missing.h5"):
        with pytest.raises(RunReadError):
            with open_run(tmp_path / name):
                pass


@pytest.mark.parametrize("config, message", [
    ("model: dsmc\n  seed: [1\n", "attribute config: is not valid YAML"),
    ("[1, 2]\n", "attribute config: is not a YAML mapping"),
    ("seed: 1\nensembles: 4\n", "attribute config: has no model"),
    ("model: boltzmann\n", "attribute config: has an unknown model 'boltzmann'"),
])
def test_a_config_that_is_not_yaml_or_lacks_a_model(outputs, tmp_path, config, message):
    path = tmp_path / "out.h5"
    shutil.copyfile(outputs["intruder"], path)
    with h5py.File(path, "a") as f:
        f.attrs["config"] = config
    expect_error(path, message)
    with h5py.File(path, "r") as f, pytest.raises(RunReadError, match=message):
        read_config(f)


def test_malformed_datasets_and_attributes_are_named(outputs, tmp_path):
    def damaged(name, edit):
        path = tmp_path / f"{name}.h5"
        shutil.copyfile(outputs["dsmc"], path)
        with h5py.File(path, "a") as f:
            edit(f)
        return path

    expect_error(damaged("short", lambda f: replace_dataset(f, "temperature/mean", f["temperature/mean"][:-1])),
                 "dataset /temperature/mean: has shape (2,), not (3,)")
    expect_error(damaged("f32", lambda f: replace_dataset(f, "events/u_max_final",
                                                          f["events/u_max_final"][()].astype("f4"))),
                 "dataset /events/u_max_final: has dtype float32, not float64")
    expect_error(damaged("nan", lambda f: replace_dataset(f, "crit/ci", np.full(3, np.nan))),
                 "dataset /crit/ci: has non-finite values")
    expect_error(damaged("ens", lambda f: f.attrs.__setitem__("ensembles", 5)),
                 "attribute ensembles: is 5, but the config says 4")
    expect_error(damaged("prov", lambda f: f["provenance"].attrs.__setitem__("shard", "3/2")),
                 "attribute shard of /provenance: is not \"index/count\"")
    expect_error(damaged("wall", lambda f: f["provenance"].attrs.__setitem__("wall_seconds", "soon")),
                 "attribute wall_seconds of /provenance: is not a number")
    expect_error(damaged("nohist", lambda f: f.__delitem__("histogram/counts")),
                 "dataset /histogram/counts: missing (every dsmc output with dsmc.histogram has it)")
    path = damaged("prov2", lambda f: f["provenance"].attrs.__setitem__("threads", np.arange(2)))
    with h5py.File(path, "r") as f:
        assert provenance(f)["threads"].tolist() == [0, 1]  # provenance() reads what is there
    expect_error(path, "attribute threads of /provenance: is not a number")


def test_histograms_read_later_raise_run_read_error_too(outputs, tmp_path):
    path = tmp_path / "out.h5"
    shutil.copyfile(outputs["needle"], path)
    run = read_run(path)
    with h5py.File(path, "r") as f:
        offset = f["omega_histogram/counts"].id.get_chunk_info(0).byte_offset
    with open(path, "r+b") as raw:  # the chunk's Fletcher32 checksum now fails
        raw.seek(offset)
        raw.write(b"\xa5" * 8)
    assert run.histograms["velocity_histogram"]["counts"].size == 6
    with pytest.raises(RunReadError, match=r"out\.h5: cannot read dataset /omega_histogram/counts"):
        run.histograms["omega_histogram"]
    os.remove(path)
    with pytest.raises(RunReadError, match="no such file"):
        LazyHistograms(path, ["omega_histogram"])["omega_histogram"]
    with pytest.raises(KeyError, match="no histogram 'histogram'"):
        run.histograms["histogram"]


def test_run_read_error_is_an_os_error_and_a_value_error_and_pickles():
    err = RunReadError("out.h5", "dataset /events/kicks", "missing (every dsmc output has it)")
    assert isinstance(err, OSError) and isinstance(err, ValueError) and granboltz.RunReadError is RunReadError
    assert str(err) == "out.h5: dataset /events/kicks: missing (every dsmc output has it)"
    again = pickle.loads(pickle.dumps(err))
    assert str(again) == str(err) and again.path == "out.h5" and again.name == "dataset /events/kicks"


def _damaged(outputs, tmp_path, model, name, edit):
    path = tmp_path / f"{name}.h5"
    shutil.copyfile(outputs[model], path)
    with h5py.File(path, "a") as f:
        edit(f)
    return path


@pytest.mark.parametrize("name, edit, message", [
    ("batch_ci", lambda f: f.__delitem__("steady/temperature/batch/ci"),
     "dataset /steady/temperature/batch/ci: missing (every dsmc output with dsmc.steady_ci: independent has it)"),
    ("batch_group", lambda f: f.__delitem__("steady/heat_flux/batch"),
     "group /steady/heat_flux/batch: missing (every dsmc output with dsmc.steady_ci: independent has it)"),
    ("batch_nan", lambda f: replace_dataset(f, "steady/crit/batch/sigma", np.nan),
     "dataset /steady/crit/batch/sigma: has non-finite values"),
    ("batch_shape", lambda f: replace_dataset(f, "steady/bulk_velocity/batch/ci", np.zeros(2)),
     "dataset /steady/bulk_velocity/batch/ci: has shape (2,), not (3,)"),
    ("batch_estimator", lambda f: f["steady/temperature/batch"].attrs.__setitem__("estimator", "ensembles"),
     "attribute estimator of /steady/temperature/batch: is 'ensembles', not blocking"),
    ("estimator", lambda f: f["steady/temperature"].attrs.__setitem__("estimator", "blocking"),
     "attribute estimator of /steady/temperature: is 'blocking', not independent"),
    ("tau", lambda f: f["steady/temperature/batch"].attrs.__setitem__("tau_int", 0.5),
     "attribute tau_int of /steady/temperature/batch: is 0.5, but sigma, variance and samples give"),
    ("neff", lambda f: f["steady/moment_4"].attrs.__delitem__("effective_samples"),
     "attribute effective_samples of /steady/moment_4: missing (every dsmc output with dsmc.steady_ci has it)"),
    ("samples", lambda f: f["steady/crit/batch"].attrs.__setitem__("samples", 3),
     "attribute samples of /steady/crit/batch: is 3, but /steady says"),
    ("block_rows", lambda f: f["steady/crit/batch"].attrs.__setitem__("block_rows", 3),
     "attribute block_rows of /steady/crit/batch: is 3, not a power of 2"),
    ("sigma", lambda f: f.__delitem__("steady/temperature/sigma"),
     "dataset /steady/temperature/sigma: missing (every dsmc output with dsmc.steady_ci has it)"),
    ("a2", lambda f: f.__delitem__("steady/a2/sigma"),
     "dataset /steady/a2/sigma: missing (every dsmc output with dsmc.steady_from and dsmc.moments >= 2 has it)"),
    # the per-ensemble sums go with the batch subgroups they were written for
    ("ensemble_sums", lambda f: f.__delitem__("accumulators/steady_ensemble"),
     "dataset /accumulators/steady_ensemble: missing (every dsmc output with dsmc.steady_ci has it)"),
    ("component", lambda f: f.__delitem__("histogram_component/mean"),
     "dataset /histogram_component/mean: missing (every dsmc output with dsmc.histogram.component has it)"),
    ("component_acc", lambda f: replace_dataset(f, "accumulators/histogram_component_steady",
                                                f["accumulators/histogram_component_steady"][1:]),
     "dataset /accumulators/histogram_component_steady: has shape (8, 2, 72), not (9, 2, 72)"),
    ("component_rows", lambda f: f["steady/histogram_component"].attrs.__delitem__("rows"),
     "attribute rows of /steady/histogram_component: missing"),
    ("center", lambda f: f["histogram"].attrs.__setitem__("center", "origin"),
     "attribute center of /histogram: is 'origin', not 'bulk'"),
    ("component_center", lambda f: f["histogram_component"].attrs.__delitem__("center"),
     "attribute center of /histogram_component: missing (every dsmc output with dsmc.histogram.component has it)"),
])
def test_damaged_intervals_and_component_histograms_are_named(outputs, tmp_path, name, edit, message):
    read_run(outputs["dsmc_independent"])  # the undamaged file reads
    expect_error(_damaged(outputs, tmp_path, "dsmc_independent", name, edit), message)


def test_a_batch_run_needs_its_sigma_and_per_ensemble_sums(outputs, tmp_path):
    expect_error(_damaged(outputs, tmp_path, "dsmc", "sigma", lambda f: f.__delitem__("steady/temperature/sigma")),
                 "dataset /steady/temperature/sigma: missing (every dsmc output with dsmc.steady_ci has it)")
    expect_error(_damaged(outputs, tmp_path, "dsmc", "blocks", lambda f: f.__delitem__("accumulators/steady_blocks")),
                 "dataset /accumulators/steady_blocks: missing (every dsmc output with dsmc.steady_ci has it)")
    expect_error(_damaged(outputs, tmp_path, "dsmc", "ind", lambda f: f["steady/density"].attrs.__setitem__(
        "estimator", "independent")), "attribute estimator of /steady/density: is 'independent', not blocking")


def test_files_of_older_simulators_still_read(outputs, tmp_path):
    # before the batch subgroups: an independent run without them or the per-ensemble sums
    def older(f):
        for name in list(f["steady"]):
            if "batch" in f[f"steady/{name}"]:
                del f[f"steady/{name}/batch"]
        for name in ("steady_ensemble", "steady_blocks", "steady_moment_cross"):
            del f[f"accumulators/{name}"]
        del f["steady/a2"]
        del f["manifest"]  # older simulators wrote none
    run = read_run(_damaged(outputs, tmp_path, "dsmc_independent", "older", older))
    assert run.steady["temperature"].batch is None and run.steady["temperature"].estimator == "independent"
    assert "a2" not in run.steady

    # before the estimators: no steady_ci in the config, no sigma
    def oldest(f):
        config = yaml.safe_load(f.attrs["config"])
        del config["dsmc"]["steady_ci"], config["dsmc"]["histogram"]["center"]
        f.attrs["config"] = yaml.safe_dump(config)
        for name in list(f["steady"]):
            group = f[f"steady/{name}"]
            for key in ("sigma",):
                if key in group:
                    del group[key]
            for key in ("estimator", "tau_int", "effective_samples", "block_rows"):
                if key in group.attrs:
                    del group.attrs[key]
        del f["steady"].attrs["estimator"], f["histogram"].attrs["center"]
        for name in ("steady_ensemble", "steady_blocks", "steady_moment_cross"):
            del f[f"accumulators/{name}"]
        del f["steady/a2"], f["steady/a3"], f["manifest"]
    run = read_run(_damaged(outputs, tmp_path, "dsmc", "oldest", oldest))
    assert run.steady["temperature"].sigma is None and run.steady["temperature"].estimator is None
    assert "steady (t > 0.2):" in repr(run)


def test_one_ensemble_of_one_row_has_no_batch_sigma_and_reads(tmp_path):
    # the spread of one ensemble's time average cannot be measured: NaN, allowed then only
    path = tmp_path / "one.h5"
    run_binary("run", BASE / "dsmc.yaml", "-q", "--threads", "1", "-o", path, "--set", "ensembles=1",
               "--set", "dsmc.steady_from=0.3", "--set", "dsmc.steady_ci=independent")
    s = read_run(path).steady["temperature"]
    assert s.batch.estimator == "ensembles" and np.isnan(s.batch.sigma) and np.isnan(s.batch.tau_int)
    assert s.sigma == 0.0 and s.estimator == "independent"
    expect_error(_damaged({"one": path}, tmp_path, "one", "inf", lambda f: replace_dataset(
        f, "steady/temperature/batch/ci", np.inf)), "dataset /steady/temperature/batch/ci: has non-finite values")
