"""repr(run) / str(run) of read_run objects made by the simulator from the tests/bad_inputs/base
configs (one per model, plus a steady run and a shard): a few lines that say what the run is and
its values with their half-widths, never a whole array; the attributes stay as they were."""

import os
import subprocess

import numpy as np
import pytest

from granboltz.output.run import read_run
from granboltz.output.summary import format_pm
from conftest import ROOT

BINARY = os.environ.get("GRANBOLTZ_BIN", str(ROOT / "build" / "granboltz"))
BASE = ROOT / "tests" / "bad_inputs" / "base"


@pytest.fixture(scope="module")
def outputs(tmp_path_factory):
    if not os.access(BINARY, os.X_OK):
        pytest.fail(f"{BINARY} is missing: build the simulator first (make build)")
    tmp = tmp_path_factory.mktemp("summary")

    def run(config, name, *extra):
        out = tmp / f"{name}.h5"
        subprocess.run([BINARY, "run", str(config), "-o", str(out), "-q", "--threads", "1", *extra], check=True)
        return read_run(out)

    runs = {m: run(BASE / f"{m}.yaml", m) for m in ("dsmc", "intruder", "needle")}
    runs["steady"] = run(BASE / "dsmc.yaml", "steady", "--set", "dsmc.steady_from=0.2")
    runs["independent"] = run(BASE / "dsmc.yaml", "independent", "--set", "dsmc.steady_from=0.2",
                              "--set", "dsmc.steady_ci=independent")
    runs["shard"] = run(BASE / "dsmc.yaml", "shard", "--set", "shard.count=2", "--set", "shard.index=1")
    visco = tmp / "viscoelastic.yaml"
    visco.write_text((BASE / "dsmc.yaml").read_text().replace(
        "  alpha: 0.5\n", "  restitution: {law: viscoelastic, delta: 0.1}\n"))
    runs["viscoelastic"] = run(visco, "viscoelastic")
    return runs


def _short(text, lines=8):
    assert text.count("\n") <= lines and "[" not in text and "array" not in text, text
    return text


def test_a_dsmc_run_says_its_sizes_times_observables_and_final_values(outputs):
    run = outputs["dsmc"]
    text = _short(repr(run))
    assert str(run) == text and text.startswith(f"Run {run.path}")
    assert "dsmc: n = 64 particles, N = 4 ensembles, complete" in text
    assert "t = 0 … 0.5, 3 observation times" in text
    assert "observables: density, bulk_velocity, temperature," in text
    T = run.temperature
    assert f"at t = 0.5: density = 1 ± 0, temperature = {format_pm(T.mean[-1], T.ci[-1])}," in text
    assert isinstance(run.temperature.mean, np.ndarray) and run.time.shape == (3,)  # the API is unchanged


def test_a_steady_run_prints_its_steady_averages_with_sigma_and_estimator(outputs):
    run = outputs["steady"]
    text = _short(str(run), lines=12)  # each steady value says its sigma too
    s = run.steady["temperature"]
    assert "steady (t > 0.2; ± ci (σ), estimator: blocking):" in text  # N = 4: blocking
    assert f"temperature = {format_pm(s.mean, s.ci)} (σ {s.sigma:.2f})" in text
    assert "a2 = " in text and "estimator: ensembles)" in text  # a2's own estimator, where it differs
    assert "at t =" not in text
    assert repr(s) == f"Observable steady/temperature = {format_pm(s.mean, s.ci)} (σ {s.sigma:.2f}, estimator: blocking)"


def test_an_independent_run_prints_the_batch_interval_beside_its_own(outputs):
    run = outputs["independent"]
    text = _short(str(run), lines=12)
    s = run.steady["temperature"]
    assert "steady (t > 0.2; ± ci (σ), estimator: independent, batch: blocking):" in text
    assert f"temperature = {format_pm(s.mean, s.ci)} (σ {s.sigma:.2f}, batch ± {s.batch.ci:.2f})" in text


def test_a_restitution_law_is_named_in_place_of_alpha(outputs):
    text = _short(repr(outputs["viscoelastic"]))
    assert "viscoelastic restitution (delta = 0.1)" in text and "α =" not in text


def test_a_shard_says_it_is_one(outputs):
    assert "N = 4 ensembles, shard 1 of 2 (its means cover only its ensembles" in repr(outputs["shard"])


@pytest.mark.parametrize("model, names", [("intruder", ["temperature_ratio", "mean_velocity"]),
                                          ("needle", ["translational_temperature_ratio", "R"])])
def test_tv06_runs_print_their_scalar_results(outputs, model, names):
    run = outputs[model]
    text = _short(repr(run))
    assert f"{model}: N = 4 ensembles, complete; mass = " in text and "collisions = 500" in text
    for name in names:
        obs = run.observables[name]
        assert f"{name} = {format_pm(obs.mean, obs.ci)}" in text
    if model == "intruder":
        assert "(exact 0.6)" in text and "gaussian bath" in text
    assert repr(run.observables[names[0]]).startswith(f"Observable {names[0]} = ")


def test_format_pm_rounds_to_the_half_width():
    assert format_pm(1.23456, 0.01234) == "1.235 ± 0.012"
    assert format_pm(11486.2, 10167.0) == "11486 ± 10167"
    assert format_pm(2.5e-7, 1.2e-9) == "(2.500 ± 0.012)e-07"
    assert format_pm(1.0, 0.0) == "1 ± 0"
