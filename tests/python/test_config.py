"""The profiles config/quick.yaml and config/paper.yaml against workflow/schemas/config.schema.yaml."""

import copy
import re

import pytest
import yaml
from snakemake.exceptions import WorkflowError
from snakemake.utils import validate

from conftest import ROOT

SCHEMA = str(ROOT / "workflow" / "schemas" / "config.schema.yaml")
PROFILES = ["quick", "paper"]


def load(profile):
    return yaml.safe_load((ROOT / "config" / f"{profile}.yaml").read_text())


@pytest.mark.parametrize("profile", PROFILES)
def test_profile_is_valid(profile):
    validate(load(profile), SCHEMA)


def _keys(d, prefix=""):
    for k, v in d.items():
        yield prefix + k
        if isinstance(v, dict):
            yield from _keys(v, prefix + k + ".")


def test_profiles_have_the_same_keys():
    assert sorted(_keys(load("quick"))) == sorted(_keys(load("paper")))


@pytest.mark.parametrize("profile", PROFILES)
def test_every_key_of_a_profile_is_commented(profile):
    for line in (ROOT / "config" / f"{profile}.yaml").read_text().splitlines():
        if re.match(r"\s*[A-Za-z_0-9]+:", line):
            assert "#" in line, f"{profile}.yaml: key without a comment: {line!r}"


def test_paper_profile_has_the_sizes_of_grw05_table1():
    ex3 = load("paper")["grw05"]["ex3"]
    assert ex3["particles"] == [64, 256, 1024, 4096, 16384] and ex3["ensembles"] == 10000


BAD = [
    ("unknown top-level key", lambda c: c.update(sedd=1)),
    ("unknown experiment key", lambda c: c["grw05"]["ex3"].update(partcles=[64])),
    ("unknown kernel key", lambda c: c["grw05"]["ex3"]["kernel"].update(mu=1)),
    ("alpha above 1", lambda c: c["grw05"]["ex3"].update(alpha=1.5)),
    ("alpha zero", lambda c: c["grw05"]["ex3"].update(alpha=0)),
    ("one particle", lambda c: c["grw05"]["ex3"].update(particles=[1, 64])),
    ("repeated n", lambda c: c["grw05"]["ex3"].update(particles=[64, 64])),
    ("one ensemble", lambda c: c["grw05"]["ex3"].update(ensembles=1)),
    ("ensembles not an integer", lambda c: c["grw05"]["ex3"].update(ensembles=10.5)),
    ("negative seed", lambda c: c.update(seed=-1)),
    ("zero threads", lambda c: c.update(threads=0)),
    ("kernel lambda 2", lambda c: c["grw05"]["ex3"]["kernel"].update({"lambda": 2})),
    ("unknown scheme", lambda c: c["grw05"]["ex3"].update(scheme="leapfrog")),
    ("five panels", lambda c: c["grw05"]["fig1"].update(particles=[64, 128, 256, 512, 1024])),
    ("missing experiment", lambda c: c["grw05"].pop("ex3")),
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
