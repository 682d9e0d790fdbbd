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
from granboltz.output.io import RunReadError, read_dataset
from granboltz.output.run import LazyHistograms, read_run
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


def test_steady_averages_carry_sigma_and_their_estimator(dsmc_file):
    run = read_run(dsmc_file)  # N = 4 < 10 ensembles: blocking (steady_ci: batch by default)
    s = run.steady["temperature"]
    with h5py.File(dsmc_file, "r") as f:
        g = f["steady/temperature"]
        assert s.sigma == g["sigma"][()] and s.tau_int == g.attrs["tau_int"] and s.block_rows == g.attrs["block_rows"]
        assert s.effective_samples == pytest.approx(g["variance"][()] / g["sigma"][()] ** 2, rel=1e-12)
    assert s.estimator == "blocking" and s.batch is None and s.sigma > 0
    assert np.shape(run.steady["bulk_velocity"].sigma) == (3,)
    assert run.temperature.sigma is None and run.temperature.estimator is None and run.temperature.batch is None
    assert run.steady["histogram"].sigma is None  # the histogram's interval is over the ensembles, no sigma


INDEPENDENT = {**TINY, "ensembles": 12,
               "dsmc": {**TINY["dsmc"], "t_end": 2.0, "moments": 3, "steady_ci": "independent",
                        "histogram": {"shells": 16, "radius": 8.0, "component": True}}}


def test_an_independent_run_gives_the_batch_interval_beside_its_own(tmp_path):
    path = simulate(tmp_path, INDEPENDENT, "independent")
    run = read_run(path)
    s = run.steady["temperature_uncentred"]
    with h5py.File(path, "r") as f:
        g, b = f["steady/temperature_uncentred"], f["steady/temperature_uncentred/batch"]
        assert s.ci == g["ci"][()] and s.sigma == g["sigma"][()]
        assert s.batch.ci == b["ci"][()] and s.batch.sigma == b["sigma"][()] and s.batch.tau_int == b.attrs["tau_int"]
        samples = int(f["steady"].attrs["samples"])
    # the papers' interval: every (ensemble, t_m) row independent, tau_int = 1/2
    assert s.estimator == "independent" and s.tau_int == 0.5 and s.effective_samples == samples
    assert s.sigma == pytest.approx(np.sqrt(s.variance / samples), rel=1e-12) and s.ci == pytest.approx(3.2 * s.sigma)
    # the batch one of the same run: the spread of the 12 ensembles' time averages
    assert s.batch.estimator == "ensembles" and s.batch.block_rows is None
    assert s.batch.effective_samples == pytest.approx(s.variance / s.batch.sigma**2, rel=1e-12)
    assert s.batch.tau_int == pytest.approx(s.batch.sigma**2 * samples / (2 * s.variance), rel=1e-12)
    assert s.batch.ci > s.ci  # consecutive rows are correlated: the honest interval is wider
    assert run.steady["a2"].estimator == "ensembles" and run.steady["a3"].sigma > 0
    assert "batch ± " in repr(s) and "estimator: independent, batch: ensembles" in repr(run)


def test_the_component_histogram_reads_as_a_histogram(tmp_path):
    run = read_run(simulate(tmp_path, INDEPENDENT, "component"))
    assert list(run.histograms) == ["histogram", "histogram_component"]
    assert "histogram_component" not in run.observables
    h = run.histograms["histogram_component"]
    np.testing.assert_allclose(h["edges"], np.linspace(-8.0, 8.0, 17))
    assert h["mean"].shape == (run.time.size, 17) and h["counts"].dtype == np.uint64
    np.testing.assert_allclose(h["mean"].sum(axis=1), 1.0)
    # (v - V)_x of a gas at rest is symmetric: the mean of the bin centres is near 0
    centres = 0.5 * (h["edges"][1:] + h["edges"][:-1])
    assert abs(np.sum(centres * h["mean"][-1, :-1])) < 0.1
    assert run.steady["histogram_component"].mean.shape == (17,)
    with h5py.File(run.path, "r") as f:
        assert f["histogram"].attrs["center"] == b"bulk" and f["histogram_component"].attrs["center"] == b"bulk"


def test_a_weighted_run_with_the_component_histogram_reads(tmp_path):
    config = {**INDEPENDENT, "ensembles": 3,
              "dsmc": {**INDEPENDENT["dsmc"], "weights": {"method": "swpm", "kappa": 0.25, "max_particles": 128}}}
    run = read_run(simulate(tmp_path, config, "swpm"))
    np.testing.assert_allclose(run.histograms["histogram_component"]["mean"].sum(axis=1), 1.0, rtol=1e-9)
    assert run.steady["temperature"].batch.estimator == "blocking" and run.steady["temperature"].batch.block_rows >= 1


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


def test_a_run_in_the_plane_reads_with_its_dimension_and_zero_z_entries(tmp_path):
    plane = {**TINY, "dsmc": {**TINY["dsmc"], "dimension": 2}}
    run = read_run(simulate(tmp_path, plane, "plane"))
    assert run.dimension == 2 and read_run(simulate(tmp_path, TINY, "space")).dimension == 3
    assert np.all(run.bulk_velocity.mean[:, 2] == 0)
    assert np.all(run.pressure_tensor.mean[:, 2, :] == 0) and np.all(run.pressure_tensor.mean[:, :, 2] == 0)
    # T = tr P / d, and the histogram's fractions over the shell areas integrate to 1
    P = run.pressure_tensor.mean
    assert np.allclose(run.temperature.mean, (P[:, 0, 0] + P[:, 1, 1]) / 2, rtol=1e-12)
    from granboltz.analysis.tails import shell_measure

    hist = run.histograms["histogram"]
    f = hist["mean"][-1, :-1] / shell_measure(hist["edges"], 2)
    assert np.isclose(np.sum(f * shell_measure(hist["edges"], 2)) + hist["mean"][-1, -1], 1.0)
    assert np.allclose(shell_measure([0.0, 1.0, 2.0], 2), [np.pi, 3 * np.pi])
    assert np.allclose(shell_measure([0.0, 1.0], 3), [4 * np.pi / 3])
    with pytest.raises(ValueError, match="dimension must be 2 or 3"):
        shell_measure([0.0, 1.0], 4)
