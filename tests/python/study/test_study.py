"""granboltz.study: a study of four tiny points run from a folder outside the repository (the
simulator build/granboltz, or $GRANBOLTZ_BIN), a second run that runs nothing, a grid with a new
value that runs only the new points, Study.table() against read_run of each file, and one-line
errors for bad study files."""

import math
import os
import subprocess
import sys

import pytest
import yaml

from conftest import ROOT
from granboltz import study as gs
from granboltz.output.run import read_run

BINARY = os.environ.get("GRANBOLTZ_BIN", str(ROOT / "build" / "granboltz"))
BASE = {"model": "dsmc", "seed": 5, "ensembles": 4,
        "dsmc": {"particles": 200, "alpha": 0.8, "beta": 1, "kernel": {"lambda": 1, "C": 0.0795774715459477},
                 "t_end": 2, "observe_every": 0.5, "steady_from": 1}}
GRID = {"dsmc.alpha": [0.5, 0.8], "dsmc.kernel.lambda": [0.0, 1.0]}


def need_binary():
    if not os.access(BINARY, os.X_OK):
        pytest.fail(f"{BINARY} is missing: build the simulator first (make build)")


def write_study(path, grid=GRID, name="tiny", base=BASE):
    path.write_text(yaml.safe_dump({"study": name, "base": base, "grid": grid}))
    return path


def cli(cwd, *args):
    """python -m granboltz.study ARGS from `cwd`, with this tree's package and the simulator."""
    env = dict(os.environ, GRANBOLTZ_BIN=BINARY,
               PYTHONPATH=os.pathsep.join([str(ROOT / "src" / "python"), os.environ.get("PYTHONPATH", "")]))
    return subprocess.run([sys.executable, "-m", "granboltz.study", *args], cwd=cwd, env=env,
                          capture_output=True, text=True)


def mtimes(folder, pattern):
    """mtime of each file matching `pattern`, but the runner lock (which holds the last runner's pid)."""
    return {p.name: p.stat().st_mtime_ns for p in folder.glob(pattern) if p.name != gs.LOCK_NAME}


@pytest.fixture(scope="module")
def first(tmp_path_factory):
    """The tiny study run once from a temporary folder: (its folder, the run's output)."""
    need_binary()
    cwd = tmp_path_factory.mktemp("elsewhere")
    write_study(cwd / "tiny.yaml")
    out = cli(cwd, "run", "tiny.yaml", "--cores", "2")
    assert out.returncode == 0, out.stdout + out.stderr
    return cwd, out


def test_a_study_runs_from_a_folder_that_is_not_the_repository(first):
    cwd, out = first
    assert not str(cwd).startswith(str(ROOT))
    assert sorted(p.name for p in cwd.iterdir()) == ["studies", "tiny.yaml"]  # nothing else written
    folder = cwd / "studies" / "tiny"
    points = sorted(p.stem for p in (folder / "points").glob("*.yaml"))
    assert len(points) == 4 and sorted(p.stem for p in (folder / "runs").glob("*.h5")) == points
    assert "running 4 of 4 points" in out.stdout
    index = (folder / "index.csv").read_text().splitlines()
    assert index[0] == "hash,dsmc.alpha,dsmc.kernel.lambda"
    assert sorted(line.split(",", 1)[1] for line in index[1:]) == ["0.5,0.0", "0.5,1.0", "0.8,0.0", "0.8,1.0"]
    for line in index[1:]:
        h, alpha, lam = line.split(",")
        config = yaml.safe_load((folder / "points" / f"{h}.yaml").read_text())
        assert config["dsmc"]["alpha"] == float(alpha) and config["dsmc"]["kernel"]["lambda"] == float(lam)
        assert config["dsmc"]["particles"] == 200 and config["seed"] == 5  # the rest is the base
        assert gs.point_hash(config) == h and len(h) == 12
        resolved = read_run(folder / "runs" / f"{h}.h5").config  # the run is of its point (defaults added)
        assert resolved["seed"] == 5 and all(resolved["dsmc"][k] == v for k, v in config["dsmc"].items())


def test_a_second_run_runs_nothing(first):
    cwd, _ = first
    folder = cwd / "studies" / "tiny"
    before = {d: mtimes(folder, f"{d}/*") for d in ("points", "runs", "logs")}
    before["index"] = mtimes(folder, "*.*")
    out = cli(cwd, "run", "tiny.yaml", "--cores", "2")
    assert out.returncode == 0, out.stderr
    assert "nothing to run" in out.stdout and "Finished job" not in out.stdout + out.stderr
    after = {d: mtimes(folder, f"{d}/*") for d in ("points", "runs", "logs")}
    after["index"] = mtimes(folder, "*.*")
    assert after == before  # point files and index not rewritten, runs not remade
    # Snakemake itself, asked for every run, sees them up to date
    hashes = [p.stem for p in (folder / "points").glob("*.yaml")]
    cmd = gs.snakemake_command(folder, [f"runs/{h}.h5" for h in hashes], BINARY, cores=1, extra=["--dry-run"])
    dry = subprocess.run(cmd, capture_output=True, text=True, cwd="/")
    assert dry.returncode == 0, dry.stderr
    assert "Nothing to be done" in dry.stdout + dry.stderr


def test_a_new_grid_value_runs_only_the_new_points(tmp_path):
    need_binary()
    write_study(tmp_path / "s.yaml", grid={"dsmc.alpha": [0.5, 0.8]}, name="grow")
    assert cli(tmp_path, "run", "s.yaml").returncode == 0
    folder = tmp_path / "studies" / "grow"
    old_runs, old_points = mtimes(folder, "runs/*.h5"), mtimes(folder, "points/*.yaml")
    assert len(old_runs) == 2
    write_study(tmp_path / "s.yaml", grid={"dsmc.alpha": [0.5, 0.8, 0.9]}, name="grow")
    out = cli(tmp_path, "run", "s.yaml")
    assert out.returncode == 0, out.stderr
    assert "running 1 of 3 points" in out.stdout
    new_runs = mtimes(folder, "runs/*.h5")
    assert len(new_runs) == 3 and all(new_runs[k] == v for k, v in old_runs.items())
    assert all(mtimes(folder, "points/*.yaml")[k] == v for k, v in old_points.items())
    # a smaller grid: the index lists its points only, the other files stay
    write_study(tmp_path / "s.yaml", grid={"dsmc.alpha": [0.9]}, name="grow")
    out = cli(tmp_path, "run", "s.yaml")
    assert out.returncode == 0 and "nothing to run" in out.stdout
    assert len((folder / "index.csv").read_text().splitlines()) == 2
    assert mtimes(folder, "runs/*.h5") == new_runs
    assert list(gs.Study(folder).table()["dsmc.alpha"]) == [0.9]


def test_the_table_matches_the_files(first, monkeypatch):
    cwd, _ = first
    folder = cwd / "studies" / "tiny"
    study = gs.Study(folder)
    table = study.table()
    assert len(table) == 4 and list(table.columns[:3]) == ["dsmc.alpha", "dsmc.kernel.lambda", "hash"]
    for name in ("temperature", "temperature_ci", "a2", "a2_ci", "a3", "a3_ci"):
        assert name in table.columns
    assert table["steady"].all()
    for _, row in table.iterrows():
        run = read_run(folder / "runs" / f"{row['hash']}.h5")
        assert run.config["dsmc"]["alpha"] == row["dsmc.alpha"]
        assert run.config["dsmc"]["kernel"]["lambda"] == row["dsmc.kernel.lambda"]
        for name in ("temperature", "a2", "a3"):
            assert row[name] == float(run.steady[name].mean)
            assert row[f"{name}_ci"] == float(run.steady[name].ci)
    # the study file gives the same folder (from its directory), and the package exports Study
    import granboltz

    monkeypatch.chdir(cwd)
    same = granboltz.Study("tiny.yaml").table()
    assert same.equals(table)
    printed = cli(cwd, "table", "tiny.yaml", "--csv")
    assert printed.returncode == 0 and printed.stdout.splitlines()[0].startswith("dsmc.alpha,dsmc.kernel.lambda,hash")
    assert len(printed.stdout.splitlines()) == 5


def test_a_run_without_steady_averages_gives_its_last_row(tmp_path):
    need_binary()
    base = {**BASE, "dsmc": {k: v for k, v in BASE["dsmc"].items() if k != "steady_from"}}
    write_study(tmp_path / "s.yaml", grid={"dsmc.alpha": [0.7]}, name="series", base=base)
    study = gs.run(tmp_path / "s.yaml", cores=1, into=tmp_path / "out", quiet=True)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out", "s.yaml"]  # --into: only there
    row = study.table().iloc[0]
    run = read_run(study.run_path(row["hash"]))
    assert not row["steady"] and row["time"] == 2.0
    assert row["temperature"] == run.temperature.mean[-1] and row["a2_ci"] == run.a2.ci[-1]


def test_missing_runs_raise_or_are_marked(tmp_path):
    write_study(tmp_path / "s.yaml", name="none")
    folder, points = gs.prepare(tmp_path / "s.yaml", into=tmp_path)
    study = gs.Study(folder)
    with pytest.raises(gs.StudyError, match="4 of 4 points have no sound run .* missing; "):
        study.table()
    table = study.table(missing="skip")
    assert table["missing"].all() and len(table) == 4 and "temperature" not in table.columns


BAD = [
    ("study: [a\n", "not YAML"),
    ("- 1\n", "a study file is a mapping"),
    ({"study": "has space", "base": BASE, "grid": GRID}, "study must be a name"),
    ({"base": BASE, "grid": GRID}, "study must be a name"),
    ({"study": "s", "grid": GRID}, "base must be a config mapping"),
    ({"study": "s", "base": BASE}, "grid must be a non-empty mapping"),
    ({"study": "s", "base": BASE, "grid": {"dsmc.alpha": []}}, "grid.dsmc.alpha must be a non-empty list"),
    ({"study": "s", "base": BASE, "grid": {"dsmc.alpha": 0.5}}, "grid.dsmc.alpha must be a non-empty list"),
    ({"study": "s", "base": BASE, "grid": {"dsmc.alpha": [0.5, 0.5]}}, "repeats a value"),
    ({"study": "s", "base": BASE, "grid": {"dsmc..alpha": [0.5]}}, "is not a dotted config key"),
    ({"study": "s", "base": BASE, "grid": {"dsmc.alpha.x": [0.5]}}, "dsmc.alpha is not a mapping"),
    ({"study": "s", "base": BASE, "grid": GRID, "seeds": [1]}, "unknown key 'seeds'"),
]


@pytest.mark.parametrize("content, message", BAD, ids=[m for _, m in BAD])
def test_bad_study_files_give_one_line_errors(tmp_path, content, message):
    path = tmp_path / "bad.yaml"
    path.write_text(content if isinstance(content, str) else yaml.safe_dump(content))
    with pytest.raises(gs.StudyError, match=message) as e:
        gs.load_study(path)
    assert "\n" not in str(e.value) and str(path) in str(e.value)


def test_the_command_line_prints_one_line_and_writes_nothing(tmp_path):
    write_study(tmp_path / "bad.yaml", grid={"dsmc.alpha": []})
    out = cli(tmp_path, "run", "bad.yaml")
    assert out.returncode == 2 and out.stdout == ""
    assert out.stderr.count("\n") == 1 and out.stderr.startswith("granboltz.study: error: ")
    missing = cli(tmp_path, "run", "nowhere.yaml")
    assert missing.returncode == 2 and "cannot read the study file" in missing.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.yaml"]


def test_a_point_the_simulator_refuses_is_refused_before_anything_runs(tmp_path):
    write_study(tmp_path / "s.yaml", grid={"dsmc.alpha": [0.5, 1.5]}, name="broken")  # alpha > 1: the parser refuses
    out = cli(tmp_path, "run", "s.yaml")
    assert out.returncode == 2 and out.stderr.count("\n") == 1
    assert "(dsmc.alpha=1.5): dsmc.alpha = 1.5: must satisfy 0 < alpha <= 1" in out.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.yaml"]


def test_a_failing_point_fails_the_run(tmp_path):
    fake = tmp_path / "fake-granboltz"  # a simulator that fails every run (the configs are sound)
    fake.write_text("#!/bin/sh\necho 'granboltz: error: out of luck' >&2\nexit 1\n")
    fake.chmod(0o755)
    write_study(tmp_path / "s.yaml", grid={"dsmc.alpha": [0.5]}, name="broken")
    env = dict(os.environ, GRANBOLTZ_BIN=str(fake),
               PYTHONPATH=os.pathsep.join([str(ROOT / "src" / "python"), os.environ.get("PYTHONPATH", "")]))
    out = subprocess.run([sys.executable, "-m", "granboltz.study", "run", "s.yaml"], cwd=tmp_path, env=env,
                         capture_output=True, text=True)
    assert out.returncode == 1 and "Snakemake failed" in out.stderr
    folder = tmp_path / "studies" / "broken"
    assert not list((folder / "runs").glob("*.h5")) and "out of luck" in next((folder / "logs").iterdir()).read_text()


def test_the_simulator_is_found_or_named(monkeypatch, tmp_path):
    monkeypatch.setenv("GRANBOLTZ_BIN", str(tmp_path / "nothing"))
    with pytest.raises(gs.StudyError, match="GRANBOLTZ_BIN=.* is not an executable"):
        gs.find_binary()
    monkeypatch.delenv("GRANBOLTZ_BIN")
    if os.access(ROOT / "build" / "granboltz", os.X_OK):
        assert gs.find_binary() == str(ROOT / "build" / "granboltz")


def test_the_hash_is_of_the_canonical_config():
    a = {"b": 1, "a": {"y": 0.5, "x": [1, 2]}}
    b = {"a": {"x": [1, 2], "y": 0.5}, "b": 1}
    assert gs.point_hash(a) == gs.point_hash(b) and len(gs.point_hash(a)) == 12
    assert gs.point_hash(a) != gs.point_hash({**a, "b": 2})
    points = gs.expand(gs.check_study({"study": "s", "base": BASE, "grid": GRID}))
    assert [v for _, v, _ in points] == [{"dsmc.alpha": a, "dsmc.kernel.lambda": l}
                                          for a in (0.5, 0.8) for l in (0.0, 1.0)]
    assert BASE["dsmc"]["alpha"] == 0.8 and not math.isnan(points[0][2]["dsmc"]["alpha"])  # base untouched


def test_the_studies_section_of_the_docs_runs_as_written(tmp_path):
    need_binary()
    from test_docs_python import DOC, code_blocks

    blocks = code_blocks(DOC.read_text(), "## Studies")
    assert sorted(lang for lang, _, _ in blocks) == ["python", "python", "sh", "yaml", "yaml"]
    (_, info, study), (_, mass_info, mass) = [b for b in blocks if b[0] == "yaml"]
    mass_python, python = sorted((b[2] for b in blocks if b[0] == "python"), key=lambda code: "mass.yaml" not in code)
    (tmp_path / info.removeprefix("file=")).write_text(study)
    assert gs.load_study(tmp_path / "scan.yaml")["grid"] == GRID  # the example is the tests' grid
    env = dict(os.environ, GRANBOLTZ_BIN=BINARY,
               PYTHONPATH=os.pathsep.join([str(ROOT / "src" / "python"), os.environ.get("PYTHONPATH", "")]))
    out = subprocess.run([sys.executable, "-c", python], cwd=tmp_path, env=env, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    printed = out.stdout.splitlines()
    assert printed[-5].split() == ["dsmc.alpha", "a2", "a2_ci"] and len(printed[-4:]) == 4
    # the mixture over a species' mass with replicas, as written
    (tmp_path / mass_info.removeprefix("file=")).write_text(mass)
    out = subprocess.run([sys.executable, "-c", mass_python], cwd=tmp_path, env=env, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    printed = out.stdout.splitlines()
    assert printed[0].split()[:2] == ["dsmc.species.heavy.mass", "replicas"] and len(printed) == 3, out.stdout
    assert [line.split()[1] for line in printed[1:]] == ["3", "3"] and (tmp_path / "mass.png").stat().st_size > 1000
