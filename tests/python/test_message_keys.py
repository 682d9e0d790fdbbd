"""Every config key that a message of the simulator or the package names is a key of the schema.

A message that names a key the user cannot write (`dsmc.initial_temperature` for
`dsmc.initial.temperature`) sends them looking for something that does not exist. The schema is
taken from the reader itself: for every section, `granboltz validate` with an unknown key lists
the keys allowed there. The keys named in messages are the dotted names inside the string
literals of src/ (C++ and Python).
"""

import os
import pathlib
import re
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
BINARY = os.environ.get("GRANBOLTZ_BIN", str(ROOT / "build" / "granboltz"))

DSMC = """model: dsmc
seed: 1
dsmc:
  particles: 64
  beta: 1
  kernel: {lambda: 1, C: 0.08}
  t_end: 1
"""
INTRUDER = """model: intruder
seed: 1
intruder: {bath: {kind: gaussian, a: 1}, mass: 1, alpha: 0.5, collisions: 10}
"""
NEEDLE = """model: needle
seed: 1
needle: {mass: 1, alpha: 0.5, collisions: 10}
"""
ALPHA = ["dsmc.alpha=0.5"]
WEIGHTS = ALPHA + ["dsmc.weights.method=swpm", "dsmc.weights.kappa=1",
                   "dsmc.weights.max_particles=100"]
# (section, config, --set values that make the section valid up to its unknown key)
SECTIONS = [
    ("", DSMC, ALPHA),
    ("", INTRUDER, []),
    ("", NEEDLE, []),
    ("shard", DSMC, ALPHA + ["shard.index=0", "shard.count=1"]),
    ("checkpoint", DSMC, ALPHA + ["checkpoint.every_seconds=1"]),
    ("dsmc", DSMC, ALPHA),
    ("dsmc.kernel", DSMC, ALPHA),
    ("dsmc.initial", DSMC, ALPHA),
    ("dsmc.histogram", DSMC, ALPHA + ["dsmc.histogram.shells=4", "dsmc.histogram.radius=5"]),
    ("dsmc.weights", DSMC, WEIGHTS),
    ("dsmc.weights.split", DSMC, WEIGHTS + ["dsmc.weights.split.radius=2",
                                            "dsmc.weights.split.rate=1",
                                            "dsmc.weights.split.interval=0.5"]),
    ("dsmc.drag", DSMC, ALPHA + ["dsmc.drag.gamma=1"]),
    ("dsmc.shear", DSMC, ALPHA + ["dsmc.shear.rate=1"]),
    ("dsmc.roughness", DSMC, ALPHA + ["dsmc.roughness.beta=0.5", "dsmc.roughness.inertia=0.4"]),
    ("dsmc.restitution", DSMC, ["dsmc.restitution.law=viscoelastic",
                                "dsmc.restitution.delta=0.1"]),
    ("dsmc.restitution", DSMC, ["dsmc.restitution.law=constant", "dsmc.restitution.alpha=0.5"]),
    ("dsmc.species[0]", DSMC, ALPHA + ["dsmc.species=[{name: a, fraction: 1, zzz: 1}]"]),
    ("intruder", INTRUDER, []),
    ("intruder.bath", INTRUDER, []),
    ("intruder.histogram", INTRUDER, ["intruder.histogram.bins=4", "intruder.histogram.range=3"]),
    ("needle", NEEDLE, []),
    ("needle.velocity_histogram", NEEDLE, ["needle.velocity_histogram.bins=4",
                                           "needle.velocity_histogram.range=3"]),
    ("needle.omega_histogram", NEEDLE, ["needle.omega_histogram.bins=4",
                                        "needle.omega_histogram.range=3"]),
]


def normal(key):
    """species[1].mass and species[i].mass are one key."""
    return re.sub(r"\[[^\]]*\]", "[]", key)


@pytest.fixture(scope="module")
def schema(tmp_path_factory):
    if not os.access(BINARY, os.X_OK):
        pytest.fail(f"{BINARY} is missing: build the simulator first (make build)")
    keys = set()
    for section, text, sets in SECTIONS:
        config = tmp_path_factory.mktemp("c") / "c.yaml"
        config.write_text(text)
        unknown = [] if section.startswith("dsmc.species") else [
            (section + "." if section else "") + "zzz=1"]
        args = [BINARY, "validate", str(config)]
        for s in sets + unknown:
            args += ["--set", s]
        r = subprocess.run(args, capture_output=True, text=True, timeout=60)
        m = re.search(r": unknown key; allowed here: (.*)$", r.stderr.strip())
        assert m, (section, r.stderr)
        prefix = section + "." if section else ""
        for k in m.group(1).split(", "):
            keys.add(normal(prefix + k))
            # sections are keys too: dsmc.histogram as well as dsmc.histogram.shells
    for k in list(keys):
        parts = k.split(".")
        for i in range(1, len(parts)):
            keys.add(".".join(parts[:i]))
    return keys


LITERAL = re.compile(r'"((?:[^"\\\n]|\\.)*)"' + r"|'((?:[^'\\\n]|\\.)*)'")
KEY = re.compile(r"(?<![\w./-])((?:dsmc|intruder|needle|shard|checkpoint)\."
                 r"[A-Za-z_]\w*(?:\.[A-Za-z_]\w*|\[\w*\])*)")


def named_keys():
    """(key, file) for every dotted config key inside a string literal of src/."""
    out = []
    files = [*ROOT.glob("src/**/*.cpp"), *ROOT.glob("src/**/*.hpp"),
             *ROOT.glob("src/python/**/*.py")]
    for f in files:
        for m in LITERAL.finditer(f.read_text()):
            for k in KEY.findall(m.group(1) or m.group(2) or ""):
                out.append((k, str(f.relative_to(ROOT))))
    return out


def test_the_scan_finds_the_keys_messages_name():
    keys = {k for k, _ in named_keys()}
    assert {"dsmc.initial.temperature", "dsmc.kernel.C", "intruder.sample_every"} <= keys


def test_every_key_a_message_names_is_in_the_schema(schema):
    wrong = sorted({(k, f) for k, f in named_keys() if normal(k) not in schema})
    assert not wrong, f"keys named in messages but not in the schema: {wrong}"
