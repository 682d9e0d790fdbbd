"""Outputs observed at log-spaced or listed times (dsmc.observe): read_run reads them (the steady
window's rows, the blocking levels and every layout check follow the stored times, not a uniform
grid), /time holds the times asked for, and the steady histogram of local_exponent sums the rows
the simulator averaged."""

import h5py
import numpy as np
import pytest

from granboltz.analysis import local_exponent as le
from granboltz.output.run import read_run
from conftest import BASE, run_binary


def run(tmp_path, observe, *sets):
    path = tmp_path / "out.h5"
    run_binary("run", BASE / "dsmc_observe.yaml", "-q", "--threads", "1", "-o", path, "--set",
               f"dsmc.observe={observe}", "--set", "ensembles=12", "--set", "dsmc.histogram.shells=10",
               "--set", "dsmc.histogram.radius=5", *sets)
    return path


@pytest.mark.parametrize("steady_from", [0.1, 0.0, 0.2])
def test_log_grid_is_read_with_the_simulators_steady_rows(tmp_path, steady_from):
    path = run(tmp_path, "{log: {from: 0.001, per_decade: 4}}", "--set", f"dsmc.steady_from={steady_from}")
    r = read_run(path)
    expected = np.append(0.0, [0.001 * 10 ** (j / 4) for j in range(11)] + [0.5])
    np.testing.assert_array_equal(r.time, expected)  # 0.001 10^(j/4) is computed as the simulator does
    rows = r.time > steady_from  # 0.1 is a time of the grid: the window starts after it
    with h5py.File(path) as f:
        assert int(f["accumulators"].attrs["steady_samples"]) == 12 * rows.sum()
        counts = f["histogram/counts"][rows, :-1].sum(axis=0)
    np.testing.assert_array_equal(le.shells_from_h5(path, steady=True)["counts"], counts)
    assert "temperature" in r.steady


def test_listed_times_are_stored_with_t_end(tmp_path):
    r = read_run(run(tmp_path, "{times: [0.01, 0.02, 0.3]}", "--set", "dsmc.steady_from=0.02"))
    np.testing.assert_array_equal(r.time, [0.0, 0.01, 0.02, 0.3, 0.5])
    assert r.config["dsmc"]["observe"] == {"times": [0.01, 0.02, 0.3, 0.5]}
    assert "observe_every" not in r.config["dsmc"]
