"""granboltz.read_run on files written by the simulator (build/granboltz on tiny configs): time,
observables with their ci, lazy histograms, events, config, provenance, shards and merge, and the
error naming the file and the dataset when HDF5 cannot read one."""

import os
import subprocess

import h5py
import numpy as np
import pytest
import yaml

import granboltz
from granboltz.io import RunReadError, read_dataset
from granboltz.run import LazyHistograms, read_run
from conftest import ROOT

BINARY = os.environ.get("GRANBOLTZ_BIN", str(ROOT / "build" / "granboltz"))
TINY = {"model": "dsmc", "seed": 3, "ensembles": 4,
        "dsmc": {"particles": 64, "alpha": 0.5, "beta": 1.0, "gamma": 4.0, "kernel": {"lambda": 0, "C": 0.0795774715459477},
                 "t_end": 1.0, "observe_every": 0.25, "histogram": {"shells": 16, "radius": 8.0}, "steady_from": 0.5}}
INTRUDER = {"model": "intruder", "seed": 5, "ensembles": 3,
            "intruder": {"mass": 1.0, "alpha": 0.5, "collisions": 2000, "bath": {"kind": "gaussian", "a": 0.5},
                         "histogram": {"bins": 20, "range": 4.0}}}


def simulate(tmp_path, config, name, *extra):
    """Run the simulator on `config`; the path of its output."""
    if not os.access(BINARY, os.X_OK):
        pytest.fail(f"{BINARY} is missing: build the simulator first (make build)")
    cfg, out = tmp_path / f"{name}.yaml", tmp_path / f"{name}.h5"
    cfg.write_text(yaml.safe_dump(config))
    subprocess.run([BINARY, "run", str(cfg), "-o", str(out), "-q", "--threads", "1", *extra], check=True)
    return out


@pytest.fixture(scope="module")
def dsmc_file(tmp_path_factory):
    return simulate(tmp_path_factory.mktemp("dsmc"), TINY, "tiny")


def test_read_run_gives_time_and_every_observable_with_its_ci(dsmc_file):
    run = read_run(dsmc_file)
    with h5py.File(dsmc_file, "r") as f:
        np.testing.assert_array_equal(run.time, f["time"][()])
        np.testing.assert_array_equal(run.temperature.mean, f["temperature/mean"][()])
        np.testing.assert_array_equal(run.temperature.ci, f["temperature/ci"][()])
        np.testing.assert_array_equal(run["heat_flux"].variance, f["heat_flux/variance"][()])
    np.testing.assert_allclose(run.time, np.arange(0.0, 1.0 + 1e-9, 0.25))
    assert {"temperature", "temperature_uncentred", "bulk_velocity", "pressure_tensor", "crit"} <= set(run.observables)
    assert run.bulk_velocity.mean.shape == (run.time.size, 3)
    np.testing.assert_allclose(run.temperature.upper - run.temperature.lower, 2 * run.temperature.ci)
    assert run.model == "dsmc" and run.ensembles == 4 and run.config["dsmc"]["particles"] == 64
    assert run.provenance["version"] and run.provenance["threads"] == 1
    assert run.events["collisions"].shape == (4,)
    assert set(run.steady) >= {"temperature"} and np.ndim(run.steady["temperature"].mean) == 0
    assert run.complete and run.shard is None
    with pytest.raises(AttributeError, match="no attribute or observable 'temprature'"):
        run.temprature


def test_read_run_gives_a2_a3_and_the_steady_sigma(tmp_path):
    config = {**TINY, "ensembles": 12, "dsmc": {**TINY["dsmc"], "moments": 3}}
    run = read_run(simulate(tmp_path, config, "sonine"))
    m2, m4, m6 = (run[f"moment_{k}"].mean for k in (2, 4, 6))
    a2 = 0.6 * m4 / m2**2 - 1
    np.testing.assert_allclose(run.a2.mean, a2, rtol=0, atol=1e-12)
    np.testing.assert_allclose(run.a3.mean, 1 + 3 * a2 - 9 / 35 * m6 / m2**3, rtol=0, atol=1e-12)
    assert run.a2.ci.shape == run.time.shape and np.all(run.a3.ci >= 0) and run.a2.variance is None
    assert np.ndim(run.steady["a2"].mean) == 0 and run.steady["a3"].ci > 0
    with h5py.File(run.path, "r") as f:
        assert bytes(f["steady/temperature"].attrs["estimator"]) == b"ensembles"
        assert bytes(f["steady/a2"].attrs["estimator"]) == b"ensembles"
        assert f["steady/temperature/sigma"].shape == ()


def test_package_exposes_read_run_without_importing_it_eagerly():
    assert granboltz.read_run is read_run
    assert granboltz.RunReadError is RunReadError


def test_histograms_are_read_only_when_asked_for(dsmc_file, monkeypatch):
    run = read_run(dsmc_file)
    assert isinstance(run.histograms, LazyHistograms) and list(run.histograms) == ["histogram"]
    assert run.histograms._cache == {}
    hist = run.histograms["histogram"]
    assert hist["mean"].shape == (run.time.size, 17) and hist["edges"].size == 17
    np.testing.assert_allclose(hist["mean"].sum(axis=1), 1.0)
    assert "histogram" in run.histograms._cache
    with pytest.raises(KeyError, match="no histogram 'omega_histogram'"):
        run.histograms["omega_histogram"]


def test_a_shard_is_marked_incomplete_and_the_merged_file_is_whole(tmp_path):
    shards = [simulate(tmp_path, TINY, f"s{i}", "--set", "shard.count=2", "--set", f"shard.index={i}") for i in (0, 1)]
    first = read_run(shards[0])
    assert first.shard == (0, 2) and not first.complete
    merged = tmp_path / "merged.h5"
    subprocess.run([BINARY, "merge", *map(str, shards), "-o", str(merged)], check=True)
    whole = read_run(merged)
    assert whole.shard is None and whole.complete
    np.testing.assert_array_equal(whole.temperature.mean, read_run(simulate(tmp_path, TINY, "whole")).temperature.mean)


def test_tv06_outputs_read_the_same_way(tmp_path):
    run = read_run(simulate(tmp_path, INTRUDER, "intruder"))
    assert run.model == "intruder" and run.time is None
    ratio = run.temperature_ratio
    assert np.ndim(ratio.mean) == 0 and ratio.per_ensemble.shape == (3,)
    assert float(run.exact["temperature_ratio"]) == pytest.approx(1.5 / 2.5)
    assert run.histograms["histogram"]["counts"].size == 20


def test_an_unreadable_dataset_names_the_file_and_the_dataset(tmp_path):
    # a Fletcher32-checksummed dataset whose stored bytes are then damaged: HDF5 refuses to read it
    path = tmp_path / "damaged.h5"
    with h5py.File(path, "w") as f:
        f.attrs["config"] = yaml.safe_dump(TINY)
        f.attrs["ensembles"] = 4
        f.create_dataset("time", data=np.linspace(0.0, 1.0, 64), chunks=(64,), fletcher32=True)
        offset = f["time"].id.get_chunk_info(0).byte_offset
    with open(path, "r+b") as raw:
        raw.seek(offset + 8)
        raw.write(b"\xff" * 8)
    with pytest.raises(RunReadError, match=r"damaged\.h5: cannot read dataset /time"):
        read_run(path)
    with h5py.File(path, "r") as f, pytest.raises(RunReadError) as err:
        read_dataset(f, "time")
    assert err.value.path == str(path) and err.value.name == "dataset /time"


def test_a_file_that_is_not_hdf5_is_named(tmp_path):
    path = tmp_path / "not.h5"
    path.write_text("not HDF5")
    with pytest.raises(RunReadError, match=r"not\.h5: cannot read the file"):
        read_run(path)
