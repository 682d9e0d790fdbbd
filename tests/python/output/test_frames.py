"""Run.to_xarray, Run.to_dataframe and the quick looks (granboltz.output.frames): the same numbers as
the Run, in d = 3 and d = 2, for a mixture and a TV06 run; the plots written as image files."""

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
import pytest  # noqa: E402

import granboltz  # noqa: E402

C = 0.0795774715459477
BASE = {"model": "dsmc", "seed": 3, "ensembles": 4,
        "dsmc": {"particles": 200, "alpha": 0.8, "beta": 1.0, "kernel": {"lambda": 0, "C": C},
                 "t_end": 2.0, "observe_every": 0.5, "steady_from": 0.5, "moments": 2}}


def _run(**dsmc):
    config = {**BASE, "dsmc": {**BASE["dsmc"], **dsmc}}
    return granboltz.simulate(config, progress=False)


def test_to_xarray_holds_the_runs_numbers_and_config():
    run = _run()
    ds = run.to_xarray()
    assert np.array_equal(ds["time"].values, run.time)
    assert np.array_equal(ds["temperature"].values, run.temperature.mean)
    assert np.array_equal(ds["temperature_ci"].values, run.temperature.ci)
    assert ds["pressure_tensor"].dims == ("time", "i", "j")
    assert np.array_equal(ds["pressure_tensor"].sel(i="x", j="y").values, run.pressure_tensor.mean[:, 0, 1])
    assert ds["bulk_velocity"].dims == ("time", "component")
    assert float(ds["steady_temperature"]) == float(run.steady["temperature"].mean)
    assert float(ds["steady_a2_ci"]) == float(run.steady["a2"].ci)
    assert ds.attrs["dsmc.alpha"] == 0.8 and ds.attrs["model"] == "dsmc" and ds.attrs["ensembles"] == 4
    assert ds.attrs["dsmc.kernel.C"] == C


def test_to_dataframe_has_one_row_per_time_and_a_ci_per_column():
    run = _run()
    df = run.to_dataframe()
    assert isinstance(df, pd.DataFrame) and df.index.name == "time"
    assert np.array_equal(df.index.to_numpy(), run.time)
    assert np.array_equal(df["temperature"].to_numpy(), run.temperature.mean)
    assert np.array_equal(df["pressure_tensor_xy_ci"].to_numpy(), run.pressure_tensor.ci[:, 0, 1])
    assert all(c + "_ci" in df.columns for c in df.columns if not c.endswith("_ci"))
    assert df.attrs["dsmc.particles"] == 200


def test_plane_runs_have_only_the_plane_components():
    run = _run(dimension=2, kernel={"lambda": 0, "C": 0.15915494309189535})
    ds, df = run.to_xarray(), run.to_dataframe()
    assert list(ds["component"].values) == ["x", "y"] and ds["pressure_tensor"].shape[1:] == (2, 2)
    assert "pressure_tensor_xy" in df.columns and "pressure_tensor_xz" not in df.columns


def test_a_mixture_has_a_species_dimension():
    run = _run(species=[{"name": "heavy", "fraction": 0.5, "mass": 2.0}, {"name": "light", "fraction": 0.5, "mass": 1.0}])
    ds = run.to_xarray()
    assert list(ds["species"].values) == ["heavy", "light"]
    assert np.array_equal(ds["species_temperature"].sel(species="heavy").values,
                          run.species["heavy"].temperature.mean)
    assert "temperature_light" in run.to_dataframe().columns


def test_a_tv06_run_gives_its_time_averages(tmp_path):
    from conftest import BASE as CONFIGS

    run = granboltz.simulate(CONFIGS / "intruder.yaml", progress=False)
    df, ds = run.to_dataframe(), run.to_xarray()
    assert len(df) == 1 and df["temperature_ratio"].iloc[0] == float(run.temperature_ratio.mean)
    assert float(ds["temperature_ratio_ci"]) == float(run.temperature_ratio.ci)


def test_quick_looks_are_written_as_images(tmp_path):
    import matplotlib.image

    run = _run()
    ax = run.plot("temperature", theory=lambda t: np.full_like(t, 2.0))
    assert len(ax.lines) == 2 and len(ax.collections) == 1  # the mean, the theory, the band
    path = tmp_path / "T.png"
    ax.figure.savefig(path)
    image = matplotlib.image.imread(path)
    assert image.ndim == 3 and image.shape[0] > 100 and image.shape[1] > 100
    assert image[..., :3].std() > 0.05  # something is drawn
    ax = run.plot("pressure_tensor", component=(0, 1))
    assert ax.get_ylabel() == "pressure_tensor[0, 1]"
    with pytest.raises(ValueError, match="component"):
        run.plot("pressure_tensor")
    with pytest.raises(KeyError, match="no observable 'nope'"):
        run.plot("nope")
    table = pd.DataFrame({"alpha": [0.9, 0.5, 0.7], "temperature": [1.0, 2.0, 1.5], "temperature_ci": [0.1] * 3})
    from granboltz.output.frames import plot_columns

    ax = plot_columns(table, "alpha", "temperature", theory=lambda a: 1 / a)
    np.testing.assert_array_equal(ax.lines[0].get_xdata(), [0.5, 0.7, 0.9])  # sorted by x
    ax.figure.savefig(tmp_path / "scan.png")
    assert matplotlib.image.imread(tmp_path / "scan.png").shape[0] > 100
