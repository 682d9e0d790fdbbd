"""read_run on mixtures (dsmc.species) and rough spheres (dsmc.roughness): run.species[name] with
its observables, a2, steady averages, attributes and events; run.temperature_rotational; and the
layout checker requiring the new datasets exactly when the stored config asks for them.

The files are a small output of the simulator (its layout, accumulators and intervals) with the
config rewritten and the mixture's and rough spheres' datasets written in by h5py, as the
simulator writes them (docs/output.md, Mixtures and rough spheres)."""

import shutil

import h5py
import numpy as np
import pytest
import yaml

from granboltz.output.io import RunReadError
from granboltz.output.run import read_run
from granboltz.output.species import largest_remainder
from conftest import BASE, run_binary

SPECIES = [{"name": "heavy", "fraction": 0.3, "mass": 4.0, "diameter": 1.0},
           {"name": "light", "fraction": 0.7, "mass": 1.0, "diameter": 1.5}]
OBS = ("density", "bulk_velocity", "temperature", "pressure_tensor", "heat_flux", "fourth_moment", "crit",
       "temperature_uncentred", "moment_2", "moment_4", "moment_6")


@pytest.fixture(scope="module")
def base_run(tmp_path_factory):
    """A one-species steady output with moments up to M6 (n = 64, 4 ensembles)."""
    path = tmp_path_factory.mktemp("mixtures") / "one.h5"
    run_binary("run", BASE / "dsmc.yaml", "-q", "--threads", "1", "-o", path, "--set", "dsmc.steady_from=0.2",
               "--set", "dsmc.moments=3", "--set", "dsmc.t_end=1")
    return path


def write_mixture(src, dst, species=SPECIES, roughness=True):
    """Copy of `src` made a mixture (dsmc.species) of rough spheres (dsmc.roughness): each species
    gets the one-species observables scaled by its index, a2/a3, steady groups and events."""
    shutil.copy(src, dst)
    with h5py.File(dst, "r+") as f:
        config = yaml.safe_load(f.attrs["config"])
        d = config["dsmc"]
        if species:
            d["species"] = species
        if roughness:
            d["roughness"] = {"beta": 0.5, "inertia": 0.4}
            d["initial"]["rotational_temperature"] = 1.0
        f.attrs["config"] = yaml.safe_dump(config)
        counts = largest_remainder([s["fraction"] for s in species], d["particles"]) if species else []
        rows = f["time"].shape[0]
        for k, (entry, count) in enumerate(zip(species or [], counts)):
            g = f.create_group(f"species/{entry['name']}")
            g.attrs.update(mass=entry["mass"], diameter=entry["diameter"], particles=np.uint64(count).item(),
                           fraction=count / d["particles"])
            g.attrs["particles"] = int(count)
            for obs in OBS:
                c = 1 + 0.1 * k  # species k: the one-species values times c (variances times c^2)
                for key in ("mean", "ci", "variance"):
                    g[f"{obs}/{key}"] = f[f"{obs}/{key}"][()] * c ** (1 + (key == "variance"))
                s = f.create_group(f"steady/species/{entry['name']}/{obs}")
                for key in ("mean", "ci", "variance", "sigma"):
                    s[key] = f[f"steady/{obs}/{key}"][()] * c ** (1 + (key == "variance"))
                for key in ("estimator", "tau_int", "effective_samples"):
                    s.attrs[key] = f[f"steady/{obs}"].attrs[key]
            for a in ("a2", "a3"):
                for key in ("mean", "ci", "bias"):
                    g[f"{a}/{key}"] = np.full(rows, 0.01 * (k + 1))
            s = f.create_group(f"steady/species/{entry['name']}/a2")
            for key in ("mean", "sigma", "ci", "bias"):
                s[key] = 0.02 * (k + 1)
            f[f"events/species/{entry['name']}/collisions"] = np.full(f["events/ensemble"].shape, 100 + k, np.uint64)
        if roughness:
            for key in ("mean", "ci", "variance"):
                f[f"temperature_rotational/{key}"] = f[f"temperature/{key}"][()] * 0.5 ** (1 + (key == "variance"))
            s = f.create_group("steady/temperature_rotational")
            for key in ("mean", "ci", "variance", "sigma"):
                s[key] = f[f"steady/temperature/{key}"][()] * 0.5 ** (1 + (key == "variance"))
            for key, value in f["steady/temperature"].attrs.items():
                s.attrs[key] = value
        ratios = ([("theta", "theta_", 0.5)] if roughness else []) + (
            [(f"temperature_ratio/{species[0]['name']}_over_{species[1]['name']}", "ratio_0_1_", 1 / 1.1)]
            if species else [])
        for group, prefix, r in ratios:  # the stored ratios (granboltz.output.ratios), as the simulator writes them
            f[f"{group}/mean"] = np.full(rows, r)
            f[f"{group}/ci"] = f["temperature/ci"][()] / f["temperature/mean"][()] * r
            f[f"{group}/bias"] = np.zeros(rows)
            s = f.create_group(f"steady/{group}")
            for key in ("mean", "sigma", "ci", "bias"):
                s[key] = r * (1.0 if key == "mean" else 0.01)
            s.attrs.update(estimator="ensembles", samples=f["steady"].attrs["samples"], **{"from": f["steady"].attrs["from"]})
            f[f"accumulators/{prefix}cross"] = np.zeros((rows, 2, 72), np.int64)
            f[f"accumulators/{prefix}steady_cross"] = np.zeros((1, 2, 72), np.int64)
    return dst


def test_a_mixture_of_rough_spheres_reads(base_run, tmp_path):
    run = read_run(write_mixture(base_run, tmp_path / "mix.h5"))
    one = read_run(base_run)
    assert one.species == {} and "temperature_rotational" not in one.observables
    assert list(run.species) == ["heavy", "light"] and "species" not in run.observables
    heavy, light = run.species["heavy"], run.species["light"]
    assert (heavy.mass, heavy.diameter, heavy.particles, light.particles) == (4.0, 1.0, 19, 45)
    assert heavy.fraction == pytest.approx(19 / 64) and light.diameter == 1.5
    np.testing.assert_array_equal(light.temperature.mean, one.temperature.mean * 1.1)
    assert heavy.temperature is heavy.observables["temperature"] and heavy.pressure_tensor.mean.shape[1:] == (3, 3)
    np.testing.assert_array_equal(light.a2.bias, 0.02)
    assert heavy.a3.mean.shape == run.time.shape
    assert heavy.steady["temperature"].sigma == pytest.approx(float(one.steady["temperature"].sigma))
    assert heavy.steady["temperature"].estimator == one.steady["temperature"].estimator
    assert float(light.steady["a2"].mean) == pytest.approx(0.04) and float(light.steady["a2"].bias) == 0.04
    assert light.events["collisions"].tolist() == [101] * run.ensembles
    assert "species" not in run.events
    np.testing.assert_array_equal(run.temperature_rotational.mean, one.temperature.mean * 0.5)
    assert float(run.steady["temperature_rotational"].mean) == pytest.approx(0.5 * float(one.steady["temperature"].mean))
    assert run.steady["temperature_rotational"].sigma is not None
    np.testing.assert_array_equal(run.theta.mean, 0.5)
    assert float(run.steady["theta"].sigma) == 0.005 and run.steady["theta"].estimator == "ensembles"
    assert list(run.temperature_ratios) == ["heavy_over_light"]
    assert float(run.steady["temperature_ratio/heavy_over_light"].mean) == pytest.approx(1 / 1.1)
    with pytest.raises(AttributeError, match="no attribute or observable 'nope'"):
        heavy.nope
    assert "heavy" in repr(heavy)


def test_largest_remainder():
    assert largest_remainder([0.3, 0.7], 64) == [19, 45]
    assert largest_remainder([1 / 3, 1 / 3, 1 / 3], 100) == [34, 33, 33]
    assert largest_remainder([0.5, 0.5], 7) == [4, 3]
    assert largest_remainder([0.25, 0.75], 1000) == [250, 750]


def _damage(path, edit):
    with h5py.File(path, "r+") as f:
        edit(f)
    return path


@pytest.mark.parametrize("edit, message", [
    (lambda f: f.__delitem__("species/heavy/temperature/mean"), r"dataset /species/heavy/temperature/mean: missing"),
    (lambda f: f.__delitem__("species/light"), r"group /species/light: missing"),
    (lambda f: f.__delitem__("species/light/a2/bias"), r"/species/light/a2/bias: missing"),
    (lambda f: f.__delitem__("steady/species/heavy/crit/sigma"), r"/steady/species/heavy/crit/sigma: missing"),
    (lambda f: f.__delitem__("steady/species/heavy/a2"), r"/steady/species/heavy/a2/mean: missing"),
    (lambda f: f.__delitem__("events/species/light/collisions"), r"/events/species/light/collisions: missing"),
    (lambda f: f.__delitem__("temperature_rotational/ci"), r"dataset /temperature_rotational/ci: missing"),
    (lambda f: f.__delitem__("steady/temperature_rotational"), r"/steady/temperature_rotational"),
    (lambda f: f["species/heavy"].attrs.__setitem__("mass", 2.0), r"attribute mass of /species/heavy: is 2"),
    (lambda f: f["species/heavy"].attrs.__setitem__("particles", 20), r"attribute particles of /species/heavy"),
    (lambda f: f["species/light"].attrs.__delitem__("fraction"), r"attribute fraction of /species/light: missing"),
    (lambda f: f["species/light/temperature/mean"].__setitem__(0, np.nan), r"/species/light/temperature/mean"),
    (lambda f: f.__delitem__("theta/ci"), r"dataset /theta/ci: missing \(every dsmc output with dsmc.roughness has it"),
    (lambda f: f.__delitem__("steady/theta/sigma"), r"/steady/theta/sigma: missing"),
    (lambda f: f["steady/theta"].attrs.__setitem__("estimator", "blocking"), r"estimator of /steady/theta"),
    (lambda f: f["temperature_ratio/heavy_over_light/mean"].__setitem__(1, np.inf),
     r"/temperature_ratio/heavy_over_light/mean"),
    (lambda f: f.__delitem__("steady/temperature_ratio/heavy_over_light/bias"), r"heavy_over_light/bias: missing"),
    (lambda f: f.__delitem__("accumulators/ratio_0_1_steady_cross"), r"ratio_0_1_steady_cross: missing"),
])
def test_a_damaged_mixture_raises_run_read_error_naming_the_dataset(base_run, tmp_path, edit, message):
    path = _damage(write_mixture(base_run, tmp_path / "mix.h5"), edit)
    with pytest.raises(RunReadError, match=message):
        read_run(path)


def test_the_new_datasets_are_required_only_when_the_config_asks(base_run, tmp_path):
    # smooth spheres: no /temperature_rotational needed; a one-species gas: no /species
    run = read_run(write_mixture(base_run, tmp_path / "smooth.h5", roughness=False))
    assert "temperature_rotational" not in run.observables and len(run.species) == 2
    rough = read_run(write_mixture(base_run, tmp_path / "rough.h5", species=None))
    assert rough.species == {} and "temperature_rotational" in rough.observables


def _with_config(path, **dsmc):
    with h5py.File(path, "r+") as f:
        config = yaml.safe_load(f.attrs["config"])
        config["dsmc"].update(dsmc)
        f.attrs["config"] = yaml.safe_dump(config)
    return str(path)


@pytest.mark.parametrize("script", ["beyond_mixture.py", "beyond_rough.py"])
def test_the_item_scripts_write_table_figure_and_summary(base_run, tmp_path, run_script, script):
    """Each item script on two synthetic mixture-of-rough-spheres files (values from the
    one-species run: the numbers mean nothing, the files' layout is the simulator's)."""
    hard = {"lambda": 1, "C": 0.0795774715459477}  # the rough theory is of hard spheres
    runs = [_with_config(write_mixture(base_run, tmp_path / f"{k}.h5"), alpha=alpha, thermostat="gaussian", kernel=hard)
            for k, alpha in enumerate((0.9, 0.7))]
    out = {key: str(tmp_path / f"item.{key}") for key in ("csv", "png", "pdf")}
    out["summary"] = str(tmp_path / "item.json")
    params = {"x1": 0.5} if script == "beyond_mixture.py" else {"kappa": 0.4}
    log = run_script(script, input={"runs": runs}, output=out, params=params)
    assert "compared with the Maxwellian approximation" in log
    header = open(out["csv"]).readline().strip().split(",")
    want = (["mass_ratio", "alpha", "t1_t2", "t1_t2_ci", "t1_t2_garzo_dufty", "difference"]
            if script == "beyond_mixture.py" else
            ["thermostat", "alpha", "beta", "theta", "theta_ci", "theta_maxwellian", "difference"])
    assert header[:len(want)] == want and len(open(out["csv"]).readlines()) == 3
    assert '"short": "compared with an approximation' in open(out["summary"]).read()


def test_an_output_of_the_simulator_with_species_and_roughness_reads(tmp_path):
    """The simulator's own mixture of rough spheres: every dataset the layout requires is there,
    the attributes match the config, and the mixture's T is sum x_i T_i."""
    config = {"model": "dsmc", "seed": 3, "ensembles": 3,
              "dsmc": {"particles": 50, "alpha": 0.8, "beta": 0.0, "kernel": {"lambda": 1, "C": 0.0795774715459477},
                       "species": [{"name": "heavy", "fraction": 0.3, "mass": 4.0, "diameter": 1.0},
                                   {"name": "light", "fraction": 0.7, "mass": 1.0, "diameter": 1.5}],
                       "roughness": {"beta": 0.5, "inertia": 0.4}, "majorant_update": "strict",
                       "thermostat": "gaussian", "moments": 3, "t_end": 1.0, "observe_every": 0.25,
                       "steady_from": 0.2}}
    (tmp_path / "mix.yaml").write_text(yaml.safe_dump(config))
    run_binary("run", tmp_path / "mix.yaml", "-q", "--threads", "1", "-o", tmp_path / "mix.h5")
    run = read_run(tmp_path / "mix.h5")
    heavy, light = run.species["heavy"], run.species["light"]
    assert (heavy.particles, light.particles, heavy.mass, light.diameter) == (15, 35, 4.0, 1.5)
    assert heavy.fraction == pytest.approx(0.3)
    x = np.array([heavy.fraction, light.fraction])
    np.testing.assert_allclose(x @ np.array([heavy.temperature.mean, light.temperature.mean]), run.temperature.mean,
                               rtol=1e-10)
    assert heavy.a2.bias.shape == run.time.shape and "a3" in light.observables
    assert np.isfinite(float(light.steady["temperature"].sigma)) and "a2" in heavy.steady
    assert run.temperature_rotational.mean.shape == run.time.shape
    assert run.steady["temperature_rotational"].estimator == run.steady["temperature"].estimator
    assert (heavy.events["collisions"] > 0).all()
    # the stored ratios: the ratios of the stored means, with their intervals
    np.testing.assert_array_equal(run.theta.mean, run.temperature_rotational.mean / run.temperature.mean)
    ratio = run.steady["temperature_ratio/heavy_over_light"]
    assert float(ratio.mean) == float(heavy.steady["temperature"].mean) / float(light.steady["temperature"].mean)
    assert np.isfinite(float(ratio.sigma)) and float(run.steady["theta"].ci) > 0
