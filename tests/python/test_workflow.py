"""The workflow as a whole: Snakemake parses it, validates the config and plans the right jobs."""

import math
import re
import subprocess

import pytest
import yaml

from conftest import ROOT, load_config

SNAKEMAKE = ["/usr/bin/snakemake", "--snakefile", "workflow/Snakefile", "--cores", "2", "--nolock"]


def snakemake(*args, cwd=ROOT):
    return subprocess.run(SNAKEMAKE + list(args), cwd=cwd, capture_output=True, text=True, timeout=300)


def job_counts(stdout):
    """{rule: count} from the 'Job stats' table of a dry run."""
    block = stdout.split("Job stats:", 1)[1].split("\n\n", 1)[0]
    rows = re.finditer(r"^(\w+)\s+(\d+)\s+\d+\s+\d+\s*$", block, re.M)
    return {m[1]: int(m[2]) for m in rows if m[1] != "total"}


ITEM_RULES = [
    *[f"grw05_{x}" for x in ("table1", "table2", "tail_exponents", "fig1", "fig2", "fig3", "fig4", "fig5", "fig6",
                             "fig7")],
    *[f"rw05_{x}" for x in ("table1", "table2", "table3_euler", "table4_strang", "table5_nosplit", "table6",
                            "effort", "steady_replicas", "fig1", "fig2", "fig3", "fig4")],
    *[f"tv06_{x}" for x in ("fig1", "fig2", "fig3", "fig4", "fig5", "fig7", "fig8", "dsmc")],
    # exact moments and local tail exponents
    "grw05_ex7_moments", "grw05_tail_local_ex7", "grw05_tail_local_ex8", "grw05_tail_local_ex9", "rw05_moments",
    "beyond_haff", "beyond_a2", "beyond_tail", "beyond_viscoelastic", "beyond_disks_a2", "beyond_mixture",
    "beyond_rough", "beyond_hcs_tail_swpm",
    # transport and rheology
    "transport_coefficients", "shear_rheology",
    # weighted particles
    "grw05_tail_swpm_ex7", "grw05_tail_swpm_ex8", "grw05_tail_swpm_ex9", "grw05_tail_swpm_check",
]


def expected_tv06_runs(config):
    """TV06 runs: one per alpha (Fig. 3), per (M, alpha) (Figs. 4-5, Fig. 7, and both methods of
    §4), and the one run of Fig. 8."""
    t = config["tv06"]
    grid = {name: len(t[name]["masses"]) * len(t[name]["alphas"]) for name in ("fig4", "fig7", "sec4")}
    return len(t["fig3"]["alphas"]) + grid["fig4"] + grid["fig7"] + 1 + 2 * grid["sec4"]


def expected_runs(config):
    """Simulator runs each profile must plan: every n of the GRW05 examples; RW05: transient n,
    Euler and Strang per K, the Crit runs, the steady runs (Tables 3-5), Table 6, the repeats."""
    g, r = config["grw05"], config["rw05"]
    grw05 = {ex: len(g[ex]["particles"]) for ex in ("ex3", "ex4", "ex5", "ex7", "ex8", "ex9")}
    s = r["steady"]
    rw05 = (len(r["transient"]["particles"]) + 2 * len(r["timestep"]["steps"]) + len(r["crit"]["particles"]) + 3
            + len(s["euler_steps"]) + len(s["strang_steps"]) + 1 + 3 + 2 * s["replicas"])
    return grw05, rw05


@pytest.mark.parametrize("profile", ["quick", "paper"])
def test_dry_run_plans_every_job(profile):
    config = load_config(profile)
    result = snakemake("--configfile", f"config/{profile}.yaml", "-n", "--forceall")
    assert result.returncode == 0, result.stderr + result.stdout
    counts = job_counts(result.stdout)
    grw05, rw05 = expected_runs(config)
    # Sharded experiments run one job per shard and a merge instead of one run job.
    shards = {ex: config["grw05"][ex].get("shards", 1) for ex in grw05}
    assert counts.pop("grw05_run_config") == sum(grw05.values())
    assert counts.pop("grw05_run", 0) == sum(k for ex, k in grw05.items() if shards[ex] == 1)
    assert counts.pop("grw05_shard", 0) == sum(k * shards[ex] for ex, k in grw05.items() if shards[ex] > 1)
    assert counts.pop("grw05_merge", 0) == sum(k for ex, k in grw05.items() if shards[ex] > 1)
    assert counts.pop("rw05_run") == counts.pop("rw05_run_config") == rw05
    # weighted particles: Examples 7-9 and the importance check
    assert counts.pop("grw05_swpm_run") == counts.pop("grw05_swpm_run_config") == 4
    assert counts.pop("tv06_run") == counts.pop("tv06_run_config") == expected_tv06_runs(config)
    b = config["beyond"]  # beyond the papers: 2 Haff runs, 2 thermostats x 2 kernels x alphas, the tail run if its own;
    # one viscoelastic run per delta and the elastic one; 2 thermostats x the hard-disk alphas
    beyond = 2 + 4 * len(b["a2"]["alphas"]) + (b["tail"]["ensembles"] != b["a2"]["ensembles"])
    beyond += len(b["viscoelastic"]["deltas"]) + 1 + 2 * len(b["disks_a2"]["alphas"])
    # the mixture: mass ratios x alphas; rough spheres: tangential betas x (HCS + white-noise alphas)
    beyond += len(b["mixture"]["mass_ratios"]) * len(b["mixture"]["alphas"])
    r = b["rough"]
    beyond += len(r["tangential_betas"]) * (len(r["hcs_alphas"]) + len(r["white_noise_alphas"]))
    assert counts.pop("beyond_run") == counts.pop("beyond_run_config") == beyond
    # the HCS tail with weighted particles: one run per alpha
    assert counts.pop("beyond_swpm_run") == counts.pop("beyond_swpm_run_config") == len(b["hcs_tail_swpm"]["alphas"])
    # transport: relaxation (eta and kappa per lambda = 0 and hard-sphere alpha, eta per disk alpha),
    # thermostatted shear flow (rates x alphas of each model), free hard-sphere shear flow and Green–Kubo
    t = config["transport"]
    rx, us = t["relaxation"], t["usf"]
    transport = 2 * len(rx["maxwell_alphas"]) + 2 * len(rx["alphas"]) + len(rx["disk_alphas"])
    transport += len(us["maxwell_reduced_rates"]) * len(us["maxwell_alphas"]) + len(us["reduced_rates"]) * len(
        us["alphas"]) + len(us["free_alphas"])
    gk = t["green_kubo"]  # Green–Kubo: one thermostatted HCS run per alpha of each model and dimension
    transport += sum(len(gk[k]) for k in ("maxwell_alphas", "maxwell_disk_alphas", "alphas", "disk_alphas"))
    assert counts.pop("transport_run") == counts.pop("transport_run_config") == transport
    # 11 tables and the window table; TV06 Figs. 3, 4, 7 and §4; Ex. 7 moments, amplitude, RW05
    # moments; 8 beyond (the HCS tail of weighted particles among them); 2 transport
    assert counts.pop("table_tex") == 29
    assert counts == {"all": 1, "report": 1, **{rule: 1 for rule in ITEM_RULES}}


@pytest.mark.parametrize("profile", ["quick", "paper"])
def test_dry_run_succeeds(profile):
    result = snakemake("--configfile", f"config/{profile}.yaml", "-n")
    assert result.returncode == 0, result.stderr + result.stdout


def test_physics_without_a_profile_names_the_unset_sizes():
    result = snakemake("--configfile", "config/physics.yaml", "-n")
    assert result.returncode != 0
    assert "grw05.ex3.particles" in result.stderr + result.stdout and "profile" in result.stderr + result.stdout


def test_workflow_refuses_a_bad_profile(tmp_path):
    config = load_config("quick")
    config["grw05"]["ex3"]["alpha"] = 2.0
    bad = tmp_path / "bad.yaml"
    bad.write_text(yaml.safe_dump(config))
    result = snakemake("--configfile", str(bad), "-n")
    assert result.returncode != 0
    assert "alpha" in result.stderr + result.stdout


def test_run_configs_carry_the_parameters_and_distinct_seeds(tmp_path):
    targets = [f"results/grw05/ex3/N=10/n={n}/run.yaml" for n in (64, 256)]
    result = snakemake("--configfile", str(ROOT / "config" / "quick.yaml"), "--directory", str(tmp_path),
                       *targets)
    assert result.returncode == 0, result.stderr
    first, second = (yaml.safe_load((tmp_path / t).read_text()) for t in targets)
    assert first["ensembles"] == 10 and first["dsmc"]["particles"] == 64 and second["dsmc"]["particles"] == 256
    assert first["dsmc"]["kernel"] == {"lambda": 0, "C": 0.07957747154594767}
    assert first["seed"] != second["seed"]
    again = tmp_path / "again"
    snakemake("--configfile", str(ROOT / "config" / "quick.yaml"), "--directory", str(again), targets[0])
    assert yaml.safe_load((again / targets[0]).read_text()) == first  # reruns are identical


def test_rw05_run_configs_carry_scheme_steps_and_steady_keys(tmp_path):
    targets = {
        "steady": "results/rw05/steady/euler_K=32/N=1/n=65536/run.yaml",
        "hot": "results/rw05/hot/strang_K=32/N=1/n=65536/run.yaml",
        "timestep": "results/rw05/timestep/euler_K=8/N=1000/n=4096/run.yaml",
        "replica": "results/rw05/replica_3/nosplit/N=1/n=65536/run.yaml",
        "tail": "results/grw05/ex8/N=8/n=1000000/run.yaml",
    }
    result = snakemake("--configfile", str(ROOT / "config" / "quick.yaml"), "--directory", str(tmp_path),
                       *targets.values())
    assert result.returncode == 0, result.stderr
    run = {k: yaml.safe_load((tmp_path / t).read_text()) for k, t in targets.items()}
    d = run["steady"]["dsmc"]
    assert (d["scheme"], d["steps"], d["t_end"], d["observe_every"], d["steady_from"]) == ("euler", 544, 136.0, 2.0, 8.0)
    assert d["kernel"]["C"] == pytest.approx(1 / 3.141592653589793) and d["gamma"] == 1.0 and d["beta"] == 1.0
    assert run["hot"]["dsmc"]["beta"] == 37.5 and run["hot"]["dsmc"]["scheme"] == "strang"
    d = run["timestep"]["dsmc"]
    assert (d["steps"], d["t_end"], d["observe_every"]) == (8, 8.0, 1.0) and "steady_from" not in d
    assert run["replica"]["dsmc"]["scheme"] == "nosplit" and run["replica"]["dsmc"]["steady_from"] == 8.0
    # The papers' intervals: every steady run asks for them explicitly (the default is batch).
    assert all(r["dsmc"].get("steady_ci") == "independent" for r in run.values() if "steady_from" in r["dsmc"])
    assert run["steady"]["dsmc"]["steady_ci"] == "independent" and "steady_ci" not in run["timestep"]["dsmc"]
    assert run["replica"]["seed"] != yaml.safe_load(snakemake_config_text(tmp_path))["seed"]
    d = run["tail"]["dsmc"]
    assert d["histogram"] == {"center": "origin", "shells": 128, "radius": 16.0}  # |v|, GRW05 eq. (37)
    assert d["kernel"]["lambda"] == 1 and d["t_end"] == 0.25


def test_hard_disk_run_configs_are_two_dimensional_with_their_own_seeds(tmp_path):
    config = load_config("quick")
    disks = config["beyond"]["disks_a2"]
    alpha, N, n = disks["alphas"][0], disks["ensembles"], disks["particles"]
    targets = {th: f"results/beyond/{th}/{kernel}/alpha={alpha}/N={N}/n={n}/run.yaml"
               for th, kernel in (("gaussian", "hard_disks"), ("white_noise", "hard_disks"), ("spheres", "hard_spheres"))}
    targets["spheres"] = targets["spheres"].replace("/spheres/", "/gaussian/")
    result = snakemake("--configfile", str(ROOT / "config" / "quick.yaml"), "--directory", str(tmp_path),
                       *targets.values())
    assert result.returncode == 0, result.stderr
    run = {k: yaml.safe_load((tmp_path / t).read_text()) for k, t in targets.items()}
    for th in ("gaussian", "white_noise"):
        d = run[th]["dsmc"]
        assert (d["dimension"], d["geometry"], d["moments"], d["thermostat"]) == (2, "impact", 3, th)
        assert d["kernel"] == {"lambda": 1, "C": disks["C"]} and d["alpha"] == alpha
        assert (d["t_end"], d["observe_every"], d["steady_from"], d["steady_ci"]) == (
            disks["t_end"], disks["observe_every"], disks["steady_from"], "batch")
    assert run["gaussian"]["dsmc"]["majorant"] == "pairwise" and run["gaussian"]["dsmc"]["beta"] == 0.0
    assert run["white_noise"]["dsmc"]["beta"] == disks["beta"] and "majorant" not in run["white_noise"]["dsmc"]
    assert "dimension" not in run["spheres"]["dsmc"]  # the d = 3 runs are untouched
    assert len({r["seed"] for r in run.values()}) == 3


def snakemake_config_text(tmp_path):
    target = "results/rw05/steady/nosplit/N=1/n=65536/run.yaml"
    snakemake("--configfile", str(ROOT / "config" / "quick.yaml"), "--directory", str(tmp_path), target)
    return (tmp_path / target).read_text()


@pytest.mark.parametrize("spoil,message", [
    (lambda c: c["rw05"]["fig2"].update(particles=[999]), "rw05.fig2.particles"),
    (lambda c: c["rw05"]["steady"].update(euler_steps=[3]), "rw05.steady"),
    (lambda c: c["rw05"]["crit"].update(ensembles=[4, 4]), "rw05.crit"),
    (lambda c: c["grw05"]["tails"].update(fit_window=[4.6, 4.25]), "grw05.tails"),
    (lambda c: c["transport"]["relaxation"].update(window=[0, 99]), "transport.relaxation.window"),
    (lambda c: c["transport"]["usf"].update(steady_from=1000), "transport.usf"),
])
def test_workflow_checks_keys_across_the_config(tmp_path, spoil, message):
    config = load_config("quick")
    spoil(config)
    bad = tmp_path / "bad.yaml"
    bad.write_text(yaml.safe_dump(config))
    result = snakemake("--configfile", str(bad), "-n")
    assert result.returncode != 0 and message in result.stderr + result.stdout


def test_mixture_and_rough_run_configs(tmp_path):
    config = load_config("quick")
    mix, rough = config["beyond"]["mixture"], config["beyond"]["rough"]
    m, a = mix["mass_ratios"][-1], mix["alphas"][0]
    b, ra = rough["tangential_betas"][-1], rough["hcs_alphas"][0]
    targets = {"mixture": f"results/beyond/gaussian/mixture-m{m}/alpha={a}/N={mix['ensembles']}/"
                          f"n={mix['particles']}/run.yaml",
               "rough": f"results/beyond/gaussian/rough-beta{b}/alpha={ra}/N={rough['ensembles']}/"
                        f"n={rough['particles']}/run.yaml",
               "rough_wn": f"results/beyond/white_noise/rough-beta{b}/alpha={ra}/N={rough['ensembles']}/"
                           f"n={rough['particles']}/run.yaml"}
    result = snakemake("--configfile", str(ROOT / "config" / "quick.yaml"), "--directory", str(tmp_path),
                       *targets.values())
    assert result.returncode == 0, result.stderr
    run = {k: yaml.safe_load((tmp_path / t).read_text()) for k, t in targets.items()}
    d = run["mixture"]["dsmc"]
    assert d["species"] == [{"name": "heavy", "fraction": mix["x1"], "mass": float(m), "diameter": 1.0},
                            {"name": "light", "fraction": 1 - mix["x1"], "mass": 1.0, "diameter": 1.0}]
    assert (d["thermostat"], d["alpha"], d["kernel"], d["steady_ci"]) == (
        "gaussian", a, {"lambda": 1, "C": config["beyond"]["C"]}, "batch")
    assert (d["t_end"], d["observe_every"], d["steady_from"]) == (mix["t_end"], mix["observe_every"], mix["steady_from"])
    assert "roughness" not in d and "species" not in run["rough"]["dsmc"]
    assert all(r["dsmc"]["majorant_update"] == "strict" and "majorant" not in r["dsmc"] for r in run.values())
    assert run["rough"]["dsmc"]["roughness"] == {"beta": float(b), "inertia": rough["kappa"]}
    assert run["rough"]["dsmc"]["beta"] == 0.0 and run["rough_wn"]["dsmc"]["beta"] == rough["beta"]
    assert run["rough_wn"]["dsmc"]["thermostat"] == "white_noise"
    assert len({r["seed"] for r in run.values()}) == 3


def test_transport_run_configs(tmp_path):
    """Prepared states, shear and schemes of the transport runs: a prepared T_xy (d = 2 and 3) or
    heat flux under the Gaussian thermostat; lambda = 0 with the exact map; thermostatted hard-sphere
    shear with the Strang scheme at a* nu0; free hard-sphere shear without thermostat."""
    config = load_config("quick")
    t = config["transport"]
    rx, us = t["relaxation"], t["usf"]
    ra, ua = rx["alphas"][0], us["alphas"][0]
    ma = us["maxwell_alphas"][0]
    size = f"N={rx['ensembles']}/n={rx['particles']}"
    usize = f"N={us['ensembles']}/n={us['particles']}"
    rate, mrate = us["reduced_rates"][0], us["maxwell_reduced_rates"][0]
    targets = {"eta": f"results/transport/relax_eta/hard_spheres/d3/alpha={ra}/{size}/run.yaml",
               "eta2": f"results/transport/relax_eta/hard_spheres/d2/alpha={rx['disk_alphas'][0]}/{size}/run.yaml",
               "kappa": f"results/transport/relax_kappa/maxwell/d3/alpha={rx['maxwell_alphas'][0]}/{size}/run.yaml",
               "usf": f"results/transport/usf_gaussian_a{rate}/hard_spheres/d3/alpha={ua}/{usize}/run.yaml",
               "usf0": f"results/transport/usf_gaussian_a{mrate}/maxwell/d3/alpha={ma}/{usize}/run.yaml",
               "free": f"results/transport/usf_none_a{us['free_rate']}/hard_spheres/d3/alpha={us['free_alphas'][0]}/"
                       f"{usize}/run.yaml"}
    result = snakemake("--configfile", str(ROOT / "config" / "quick.yaml"), "--directory", str(tmp_path),
                       *targets.values())
    assert result.returncode == 0, result.stderr
    run = {k: yaml.safe_load((tmp_path / v).read_text())["dsmc"] for k, v in targets.items()}
    s = rx["shear_stress"]
    assert run["eta"]["initial"]["temperature"] == [[1.0, s, 0.0], [s, 1.0, 0.0], [0.0, 0.0, 1.0]]
    assert run["eta2"]["initial"]["temperature"] == [[1.0, s], [s, 1.0]] and run["eta2"]["geometry"] == "impact"
    assert run["kappa"]["initial"] == {"temperature": 1.0, "heat_flux": [rx["heat_flux"], 0.0, 0.0]}
    assert run["kappa"]["geometry"] == "uniform" and run["kappa"]["kernel"]["lambda"] == 0
    assert all(run[k]["thermostat"] == "gaussian" for k in ("eta", "eta2", "kappa", "usf", "usf0"))
    assert run["eta"]["majorant"] == "pairwise" and "geometry" not in run["eta"]
    nu0 = 64 / 5 * math.sqrt(math.pi) * t["C_factor"] / (4 * math.pi)
    assert run["usf"]["shear"]["rate"] == pytest.approx(rate * nu0) and run["usf"]["scheme"] == "strang"
    assert run["usf0"]["shear"]["rate"] == pytest.approx(mrate) and run["usf0"]["scheme"] == "nosplit"
    assert run["free"]["thermostat"] == "none" and run["free"]["shear"]["rate"] == us["free_rate"]
    assert all(run[k]["steady_ci"] == "batch" for k in ("usf", "usf0", "free"))
