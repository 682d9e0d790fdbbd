"""Studies that speak physics: grid keys that address a species by name (or a list item by its
index), a replica axis aggregated in the table with the spread and the interval of the mean
(whose coverage is tested), a species' a2 column, and `study status`."""

import math

import numpy as np
import pandas as pd
import pytest
import yaml

from granboltz import study as gs
from granboltz.study.table import Study, aggregate_replicas
from test_study import cli, need_binary

MIXTURE = {"model": "dsmc", "seed": 11, "ensembles": 4,
           "dsmc": {"particles": 200, "alpha": 0.8, "beta": 1, "kernel": {"lambda": 0, "C": 0.0795774715459477},
                    "species": [{"name": "heavy", "fraction": 0.5, "mass": 2.0}, {"name": "light", "fraction": 0.5, "mass": 1.0}],
                    "t_end": 2, "observe_every": 0.5, "steady_from": 1, "moments": 2}}


def _write(path, **spec):
    path.write_text(yaml.safe_dump({"study": "mass", "base": MIXTURE, **spec}))
    return path


@pytest.fixture(scope="module")
def mass_study(tmp_path_factory):
    need_binary()
    cwd = tmp_path_factory.mktemp("replicas")
    _write(cwd / "mass.yaml", grid={"dsmc.species.heavy.mass": [2.0, 4.0]}, replicas=3)
    out = cli(cwd, "run", "mass.yaml", "--cores", "2")
    assert out.returncode == 0, out.stdout + out.stderr
    return cwd


def test_a_species_is_addressed_by_name_and_replicas_are_aggregated(mass_study):
    study = Study(mass_study / "studies" / "mass")
    assert study.keys == ["dsmc.species.heavy.mass", "seed"] and study.replicas == [11, 12, 13]
    for h, values in study.points:  # the name addressed the item, whatever its place in the list
        heavy = next(s for s in study.config(h)["dsmc"]["species"] if s["name"] == "heavy")
        assert heavy["mass"] == values["dsmc.species.heavy.mass"] and study.config(h)["seed"] == values["seed"]
    table = study.table()
    assert list(table["dsmc.species.heavy.mass"]) == [2.0, 4.0] and list(table["replicas"]) == [3, 3]
    each = study.table(aggregate=False)
    assert len(each) == 6 and set(each["seed"]) == {11, 12, 13}
    for mass, row in zip((2.0, 4.0), table.itertuples(index=False)):
        part = each[each["dsmc.species.heavy.mass"] == mass]
        for column in ("T_heavy/T_light", "a2_heavy", "temperature"):
            x = part[column].to_numpy()
            got = table.loc[table["dsmc.species.heavy.mass"] == mass]
            assert float(got[column].iloc[0]) == pytest.approx(x.mean(), rel=1e-15)
            assert float(got[column + "_spread"].iloc[0]) == pytest.approx(x.std(ddof=1), rel=1e-12)
            from scipy import stats

            t = stats.t.ppf(0.5 + math.erf(3.2 / math.sqrt(2)) / 2, 2)
            assert float(got[column + "_ci"].iloc[0]) == pytest.approx(t * x.std(ddof=1) / math.sqrt(3), rel=1e-12)


def test_study_status_names_missing_and_damaged_points(mass_study):
    out = cli(mass_study, "status", "mass.yaml")
    assert out.returncode == 0 and "mass: 6 of 6 points have a sound run" in out.stdout, out.stdout + out.stderr
    study = Study(mass_study / "studies" / "mass")
    h0, h1 = study.points[0][0], study.points[1][0]
    saved = study.run_path(h0).read_bytes()
    try:
        study.run_path(h0).unlink()
        study.run_path(h1).write_bytes(saved[:1000])  # a truncated file
        out = cli(mass_study, "status", "mass.yaml")
        assert out.returncode == 3, out.stdout + out.stderr
        lines = out.stdout.splitlines()
        assert any(line.startswith(h0) and line.endswith("missing") for line in lines)
        assert any(line.startswith(h1) and "damaged" in line for line in lines)
        assert lines[-1] == "mass: 4 of 6 points have a sound run (1 missing, 1 damaged)"
    finally:
        study.run_path(h0).write_bytes(saved)
        h1_run = cli(mass_study, "run", "mass.yaml", "--cores", "2")
        assert h1_run.returncode == 0, h1_run.stderr


def test_list_items_by_index_and_bad_keys_are_one_line_errors(tmp_path):
    spec = {"study": "x", "base": MIXTURE, "grid": {"dsmc.species.1.mass": [1.0, 3.0]}}
    points = gs.expand(gs.check_study(spec))
    assert [p[2]["dsmc"]["species"][1]["mass"] for p in points] == [1.0, 3.0]
    for grid, replicas, message in (
            ({"dsmc.species.medium.mass": [1.0]}, None, r"dsmc\.species has no item 'medium' \(names heavy, light, or indices 0 to 1\)"),
            ({"dsmc.species.5.mass": [1.0]}, None, "has no item '5'"),
            ({"seed": [1, 2]}, 3, "replicas and grid.seed"),
            ({"dsmc.alpha": [0.5]}, 0, "replicas = 0: must be from 1"),
            ({"dsmc.alpha": [0.5]}, [1, 1], "repeats a seed"),
            ({"dsmc.alpha": [0.5]}, "3", "a number of replicas or a list of seeds"),
            ({"dsmc.alpha": [0.5]}, [-1], "seed -1 is not an integer")):
        s = dict(spec, grid=grid)
        if replicas is not None:
            s["replicas"] = replicas
        with pytest.raises(gs.StudyError, match=message) as err:
            gs.check_study(s)
        assert "\n" not in str(err.value)
    no_seed = dict(spec, base={k: v for k, v in MIXTURE.items() if k != "seed"}, replicas=2)
    with pytest.raises(gs.StudyError, match="counts from base.seed"):
        gs.check_study(no_seed)


def test_the_replica_interval_covers_at_its_level():
    # 4000 grid points of R = 5 normal replicas: the interval of the mean covers the true mean
    # with probability 0.99863 (lambda_p = 3.2); the count of misses is Binomial(4000, 0.00137)
    # (mean 5.5): more than 16 has probability < 1e-4, and a normal-quantile interval (too
    # narrow at R = 5: it would miss ~10 %) fails far beyond.
    rng = np.random.default_rng(7)
    groups, R = 4000, 5
    x = rng.normal(2.0, 0.3, size=groups * R)
    points = [(f"h{i}", {"g": i // R, "seed": i % R}) for i in range(groups * R)]
    frame = pd.DataFrame({"hash": [h for h, _ in points], "g": [p["g"] for _, p in points],
                          "seed": [p["seed"] for _, p in points], "v": x, "v_ci": 0.0})
    table = aggregate_replicas(frame, ["g"], points)
    misses = int((np.abs(table["v"] - 2.0) > table["v_ci"]).sum())
    assert misses <= 16, misses
    assert (table["replicas"] == R).all()
