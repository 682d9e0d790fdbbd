"""The config: config/physics.yaml with a size profile (config/quick.yaml, config/paper.yaml) merged
over it, against workflow/schemas/config.schema.yaml."""

import copy
import math
import re

import pytest
import yaml
from snakemake.exceptions import WorkflowError
from snakemake.utils import validate

from conftest import ROOT, load_config

SCHEMA = str(ROOT / "workflow" / "schemas" / "config.schema.yaml")
PROFILES = ["quick", "paper"]
FILES = ["physics"] + PROFILES

# The keys a profile sets, and the only ones in which quick and paper may differ: the sizes (n, N,
# shards, collisions, t_end, replicas, rows, K and alpha lists: how many runs) and what the
# smaller size forces (fit windows, steady windows, time grids, the HCS tail run): listed in
# docs/workflow.md, "Profiles". Each stands as ~ in physics.yaml, in its place.
SIZE_KEYS = {
    "profile", "report_dir",
    *(f"grw05.{ex}.{k}" for ex in ("ex3", "ex4") for k in ("particles", "ensembles")),
    *(f"grw05.{ex}.{k}" for ex in ("ex7", "ex8", "ex9") for k in ("particles", "ensembles", "shards")),
    "grw05.tails.fit_window", "grw05.tails.windows",
    *(f"grw05.tails.swpm.{k}" for k in ("max_particles", "particles", "ensembles", "rows")),
    "rw05.transient.particles", "rw05.transient.ensembles", "rw05.timestep.ensembles", "rw05.fig2.particles",
    "rw05.crit.ensembles", "rw05.crit_schemes.ensembles", "rw05.steady.euler_steps", "rw05.steady.replicas",
    *(f"tv06.{fig}.collisions" for fig in ("fig3", "fig4", "fig7", "fig8", "sec4")), "tv06.fig5.tail_window",
    "beyond.haff.particles", "beyond.haff.ensembles",
    "beyond.a2.alphas", "beyond.a2.particles", "beyond.a2.t_end",
    *(f"beyond.tail.{k}" for k in ("alpha", "ensembles", "shells", "radius", "max_ci")),
    "beyond.hcs_tail_swpm.ensembles",
    *(f"beyond.viscoelastic.{k}" for k in ("particles", "ensembles", "t_end", "observe_every", "late_from")),
    "beyond.viscoelastic.elastic.ensembles",
    *(f"beyond.disks_a2.{k}" for k in ("alphas", "particles", "ensembles", "t_end")),
    *(f"beyond.{x}.{k}" for x in ("mixture", "rough") for k in ("particles", "ensembles", "t_end", "steady_from")),
    "beyond.rough.white_noise_alphas",
    *(f"transport.relaxation.{k}" for k in ("disk_alphas", "particles", "ensembles")),
    *(f"transport.usf.{k}" for k in ("maxwell_alphas", "alphas", "free_alphas", "particles", "ensembles", "t_end")),
    *(f"transport.green_kubo.{k}" for k in ("alphas", "disk_alphas", "ensembles", "t_end", "observe_every")),
}


def load(profile):
    return load_config(profile)


def read(name):
    return yaml.safe_load((ROOT / "config" / f"{name}.yaml").read_text())


@pytest.mark.parametrize("profile", PROFILES)
def test_profile_is_valid(profile):
    validate(load(profile), SCHEMA)


def _leaves(d, prefix=""):
    """{dotted key: value} of every value that is not a dict."""
    out = {}
    for k, v in d.items():
        if isinstance(v, dict):
            out.update(_leaves(v, prefix + k + "."))
        else:
            out[prefix + k] = v
    return out


@pytest.mark.parametrize("profile", PROFILES)
def test_a_profile_sets_the_size_keys_and_nothing_else(profile):
    assert set(_leaves(read(profile))) == SIZE_KEYS


def test_physics_leaves_the_size_keys_to_the_profiles():
    physics = _leaves(read("physics"))
    assert {k for k, v in physics.items() if v is None} == SIZE_KEYS


def test_quick_and_paper_differ_only_in_size_keys():
    """A physics value cannot drift between the profiles: the merged configs differ in sizes only."""
    quick, paper = _leaves(load("quick")), _leaves(load("paper"))
    assert set(quick) == set(paper)
    assert {k for k in quick if quick[k] != paper[k]} <= SIZE_KEYS


@pytest.mark.parametrize("name", FILES)
def test_every_key_of_a_config_file_is_commented(name):
    for line in (ROOT / "config" / f"{name}.yaml").read_text().splitlines():
        if re.match(r"\s*[A-Za-z_0-9]+:", line):
            assert "#" in line, f"{name}.yaml: key without a comment: {line!r}"


def test_paper_profile_has_the_sizes_of_the_papers():
    g, r = load("paper")["grw05"], load("paper")["rw05"]
    for ex in ("ex3", "ex4"):
        assert g[ex]["particles"] == [64, 256, 1024, 4096, 16384] and g[ex]["ensembles"] == 10000
    assert g["ex5"]["ensembles"] == 1000 and g["ex5"]["kernel"]["lambda"] == 1
    for ex, lam, R, t_end in (("ex7", 0, 40, 2.5), ("ex8", 1, 16, 0.25), ("ex9", 0.5, 24, 0.5)):
        assert g[ex]["particles"] == [10**7] and g[ex]["ensembles"] == 100 and g[ex]["kernel"]["lambda"] == lam
        assert g[ex]["histogram"] == {"shells": 128, "radius": R} and g[ex]["t_end"] == t_end
    assert g["tails"]["fit_window"] == [4.25, 4.6] and g["tails"]["k0"] == 1
    assert r["transient"]["particles"] == [16, 64, 256, 1024, 4096, 16384, 65536]
    assert r["transient"]["ensembles"] == r["timestep"]["ensembles"] == 10000 and r["timestep"]["steps"] == [4, 8, 16, 32]
    assert r["crit"]["ensembles"] == [65536, 16384, 4096] and r["crit_schemes"]["ensembles"] == 4096
    s = r["steady"]
    assert (s["particles"], s["t_end"], s["observe_every"], s["steady_from"]) == (65536, 136, 2, 8)
    assert s["euler_steps"] == [32, 256, 512, 2048, 4096] and s["strang_steps"] == [8, 16, 32, 64]
    assert r["hot"] == {"beta": 37.5, "steps": 32} and r["physics"]["kernel"]["C"] == pytest.approx(1 / math.pi)


BAD = [
    ("unknown top-level key", lambda c: c.update(sedd=1)),
    ("unknown experiment key", lambda c: c["grw05"]["ex3"].update(partcles=[64])),
    ("unknown kernel key", lambda c: c["grw05"]["ex3"]["kernel"].update(mu=1)),
    ("alpha above 1", lambda c: c["grw05"]["ex3"].update(alpha=1.5)),
    ("alpha zero", lambda c: c["grw05"]["ex3"].update(alpha=0)),
    ("one particle", lambda c: c["grw05"]["ex3"].update(particles=[1, 64])),
    ("repeated n", lambda c: c["grw05"]["ex3"].update(particles=[64, 64])),
    ("zero ensembles", lambda c: c["grw05"]["ex3"].update(ensembles=0)),
    ("ensembles not an integer", lambda c: c["grw05"]["ex3"].update(ensembles=10.5)),
    ("negative seed", lambda c: c.update(seed=-1)),
    ("zero threads", lambda c: c.update(threads=0)),
    ("kernel lambda 2", lambda c: c["grw05"]["ex3"]["kernel"].update({"lambda": 2})),
    ("unknown scheme", lambda c: c["grw05"]["ex3"].update(scheme="leapfrog")),
    ("five panels", lambda c: c["grw05"]["fig1"].update(particles=[64, 128, 256, 512, 1024])),
    ("missing experiment", lambda c: c["grw05"].pop("ex3")),
    ("unknown profile", lambda c: c.update(profile="full")),
    ("tail window key", lambda c: c["grw05"]["tails"].update(fit_windw=[1, 2])),
    ("tail window of three", lambda c: c["grw05"]["tails"].update(fit_window=[1, 2, 3])),
    ("histogram normalisation", lambda c: c["grw05"]["tails"].update(histogram="area")),
    ("histogram without shells", lambda c: c["grw05"]["ex7"]["histogram"].pop("shells")),
    ("rw05 unknown key", lambda c: c["rw05"]["steady"].update(stedy_from=8)),
    ("rw05 zero steps", lambda c: c["rw05"]["timestep"].update(steps=[0, 4])),
    ("rw05 no physics", lambda c: c["rw05"].pop("physics")),
    ("rw05 one replica", lambda c: c["rw05"]["steady"].update(replicas=1)),
    ("rw05 crit N not integer", lambda c: c["rw05"]["crit"].update(ensembles=[1.5, 2, 3])),
]


@pytest.mark.parametrize("what,spoil", BAD, ids=[b[0] for b in BAD])
def test_schema_rejects_a_bad_profile(what, spoil):
    config = copy.deepcopy(load("quick"))
    spoil(config)
    with pytest.raises(WorkflowError):
        validate(config, SCHEMA)


def test_schema_fills_defaults():
    config = load("quick")
    del config["threads"], config["grw05"]["ex3"]["majorant_update"]
    validate(config, SCHEMA)
    assert config["threads"] == 2 and config["grw05"]["ex3"]["majorant_update"] == "paper"


def test_every_schema_key_has_a_description():
    schema = yaml.safe_load(open(SCHEMA))

    def resolve(node):
        ref = node.get("$ref")
        return schema["definitions"][ref.rsplit("/", 1)[-1]] if ref else node

    def walk(node, where):
        for key, prop in node.get("properties", {}).items():
            assert "description" in prop or "description" in resolve(prop), f"{where}.{key} has no description"
            walk(resolve(prop), f"{where}.{key}")
            if "items" in resolve(prop):
                walk(resolve(resolve(prop)["items"]), f"{where}.{key}[]")

    walk(schema, "config")
    for name, definition in schema["definitions"].items():
        walk(definition, name)
