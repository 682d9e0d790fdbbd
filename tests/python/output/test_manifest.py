"""The manifest of DSMC outputs (/manifest, docs/output.md): it lists every dataset the run
presents with its shape, and read_run checks an output against it. A listed dataset missing or
of another shape, or a damaged manifest, is RunReadError naming the file and the object; a file
without /manifest (written before it existed) reads as before, checked against the layout derived
from its config."""

import os
import shutil
import subprocess

import h5py
import numpy as np
import pytest

from granboltz.output.io import RunReadError
from granboltz.output.run import read_run
from conftest import ROOT

BINARY = os.environ.get("GRANBOLTZ_BIN", str(ROOT / "build" / "granboltz"))
BASE = ROOT / "tests" / "bad_inputs" / "base"
# Histograms (both), speed moments with a2/a3 and the steady state: every observer of one species.
ONE = ["--set", "dsmc.histogram.shells=6", "--set", "dsmc.histogram.radius=5", "--set", "dsmc.histogram.component=true",
       "--set", "dsmc.steady_from=0.2", "--set", "dsmc.moments=3"]
# Weighted particles under the Gaussian thermostat: the cooling rate observer.
SWPM = ["--set", "dsmc.weights.method=swpm", "--set", "dsmc.weights.kappa=1", "--set", "dsmc.weights.max_particles=300", "--set", "dsmc.beta=0",
        "--set", "dsmc.thermostat=gaussian", "--set", "dsmc.steady_from=0.2", "--set", "dsmc.histogram.shells=4",
        "--set", "dsmc.histogram.radius=5"]
# The general gas: species rows, rotation and the ratios.
ROUGH = ["--set", "dsmc.roughness.beta=0.4", "--set", "dsmc.roughness.inertia=0.4", "--set", "dsmc.steady_from=0.2"]
SPECIES = """
  species:
    - {name: heavy, fraction: 0.5, mass: 2.0, diameter: 1.2}
    - {name: light, fraction: 0.5, mass: 1.0, diameter: 1.0}
"""
RECORD = ("accumulators", "events", "provenance", "manifest")


@pytest.fixture(scope="session")
def outputs(tmp_path_factory):
    if not os.access(BINARY, os.X_OK):
        pytest.fail(f"{BINARY} is missing: build the simulator first (make build)")
    d = tmp_path_factory.mktemp("manifest")
    paths, mixture = {}, d / "mixture.yaml"
    mixture.write_text((BASE / "dsmc.yaml").read_text().replace("dsmc:\n", "dsmc:" + SPECIES, 1))
    for name, config, extra in (("one", BASE / "dsmc.yaml", ONE), ("swpm", BASE / "dsmc.yaml", SWPM),
                                ("rough", mixture, ROUGH)):
        paths[name] = d / f"{name}.h5"
        subprocess.run([BINARY, "run", str(config), "-q", "-o", str(paths[name]), *extra], check=True)
    return paths


def presented(f):
    """{path: shape} of every dataset outside the record's groups."""
    out = {}
    f.visititems(lambda k, o: out.__setitem__("/" + k, o.shape)
                 if isinstance(o, h5py.Dataset) and k.split("/")[0] not in RECORD else None)
    return out


@pytest.mark.parametrize("name", ["one", "swpm", "rough"])
def test_manifest_lists_every_presented_dataset(outputs, name):
    run = read_run(outputs[name])
    with h5py.File(outputs[name]) as f:
        assert {p: e.shape for p, e in run.manifest.items()} == presented(f)
    assert all(e.meaning for e in run.manifest.values())
    R = run.time.size
    # The full pressure tensor and the heat flux are observables of every engine.
    assert run.manifest["/pressure_tensor/mean"].shape == (R, 3, 3)
    assert run.manifest["/heat_flux/mean"].shape == (R, 3)
    assert run.manifest["/steady/pressure_tensor/mean"].shape == (3, 3)
    observers = {e.observer for e in run.manifest.values()}
    expected = {"one": {"time", "moments", "histogram", "histogram_component"},
                "swpm": {"time", "moments", "histogram", "cooling_rate"},
                "rough": {"time", "moments", "species", "rotation", "ratios"}}[name]
    assert observers == expected


def damaged(src, tmp_path, edit, name="damaged.h5"):
    dst = tmp_path / name
    shutil.copy(src, dst)
    with h5py.File(dst, "r+") as f:
        edit(f)
    return dst


def refused(path, name, problem):
    with pytest.raises(RunReadError) as err:
        read_run(path)
    assert err.value.path == str(path) and err.value.name == name, str(err.value)
    assert problem in err.value.problem, str(err.value)


def test_a_listed_dataset_missing_is_refused(outputs, tmp_path):
    # /a2/bias is optional in the config-derived layout (older simulators lacked it): only the
    # manifest says this file must have it.
    refused(damaged(outputs["one"], tmp_path, lambda f: f.__delitem__("a2/bias")),
            "dataset /a2/bias", "missing (listed in /manifest)")


def test_a_listed_shape_that_differs_is_refused(outputs, tmp_path):
    def edit(f):
        paths = [p.decode() for p in f["manifest/path"][()]]
        shape = f["manifest/shape"][()]
        shape[paths.index("/steady/histogram/mean"), 0] += 1
        f["manifest/shape"][...] = shape
    refused(damaged(outputs["one"], tmp_path, edit), "dataset /steady/histogram/mean", "but /manifest lists")


@pytest.mark.parametrize("edit, name, problem", [
    (lambda f: f.__delitem__("manifest/rank"), "dataset /manifest/rank", "missing"),
    (lambda f: (f.__delitem__("manifest/shape"), f.create_dataset("manifest/shape", data=np.zeros(3))),
     "dataset /manifest/shape", "not unsigned integers"),
    (lambda f: (f.__delitem__("manifest/meaning"), f.create_dataset("manifest/meaning", data=np.array([b"x"], dtype="S1"))),
     "dataset /manifest/meaning", "rows, but /manifest/path has"),
    (lambda f: f["manifest/rank"].__setitem__(0, 7), "dataset /manifest/rank", "more than the"),
    (lambda f: f["manifest/path"].__setitem__(1, b"/time"), "dataset /manifest/path", "listed once"),
    (lambda f: (f.__delitem__("manifest"), f.create_dataset("manifest", data=[1])), "group /manifest",
     "is a dataset"),
])
def test_a_damaged_manifest_is_refused(outputs, tmp_path, edit, name, problem):
    refused(damaged(outputs["one"], tmp_path, edit), name, problem)


def test_an_output_without_manifest_reads_by_its_config(outputs, tmp_path):
    # As a file written before the manifest existed: checked against the config-derived layout.
    path = damaged(outputs["one"], tmp_path, lambda f: f.__delitem__("manifest"))
    old, new = read_run(path), read_run(outputs["one"])
    assert old.manifest is None and new.manifest is not None
    assert old.observables.keys() == new.observables.keys()
    for name in new.observables:
        np.testing.assert_array_equal(old.observables[name].mean, new.observables[name].mean)
    # ... and that layout still refuses what every output has
    path = damaged(path, tmp_path, lambda f: f.__delitem__("temperature/ci"), "older_damaged.h5")
    refused(path, "dataset /temperature/ci", "missing")


def test_the_digest_covers_the_manifest(outputs, tmp_path):
    # The manifest's text columns are fixed-length, so the writer's digest is the reader's:
    # `granboltz verify` passes, and refuses a manifest edited in place.
    subprocess.run([BINARY, "verify", str(outputs["one"])], check=True, capture_output=True)

    def edit(f):
        meaning = f["manifest/meaning"][()]
        meaning[0] = b"edited"
        f["manifest/meaning"][...] = meaning
    r = subprocess.run([BINARY, "verify", str(damaged(outputs["one"], tmp_path, edit))], capture_output=True, text=True)
    assert r.returncode != 0
