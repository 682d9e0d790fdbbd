"""granboltz.study refuses study files it cannot use before anything is written, in one line:
limits (points, bytes, YAML nodes with aliases expanded, nesting), keys given twice, values
that are no config values (NaN, inf, dates, huge integers), names too long for a folder, files
that are not regular UTF-8 files (a FIFO is never opened for a blocking read), and points the
simulator's parser refuses (an unknown grid key, a value out of range), naming the point. The
command line says the same in one line with exit status 2, `table` included (run as
`python -m granboltz.study`, whose StudyError must be the package's)."""

import os
import subprocess

import pytest
import yaml

from granboltz import study as gs
from test_study import BASE, GRID, cli, need_binary

BOMB = "\n".join(["    a: &a [lol, lol, lol, lol, lol, lol, lol, lol, lol]"]
                 + [f"    {c}: &{c} [{', '.join(['*' + p] * 9)}]" for p, c in zip("abcdefgh", "bcdefghi")])


def study_text(base=None, grid=None, name="s", extra=""):
    base = yaml.safe_dump(BASE if base is None else base, default_flow_style=True, width=10**6).strip()
    grid = yaml.safe_dump(GRID if grid is None else grid, default_flow_style=True, width=10**6).strip()
    return f"study: {name}\nbase: {base}\ngrid: {grid}\n{extra}"


def nested(depth):
    return "[" * depth + "1" + "]" * depth


# (id, study file text or bytes, what the one-line message must say)
BAD = [
    ("grid of a million points", study_text(grid={"seed": list(range(1000)), "dsmc.alpha": [i / 1000 for i in range(1, 1001)]}),
     "the grid has 1000000 points, more than the limit 10000 (raise it with --max-points"),
    ("alias bomb in base", "study: s\ngrid: {dsmc.alpha: [0.5]}\nbase:\n  model: dsmc\n  x:\n" + BOMB + "\n",
     "more than 100000 YAML nodes once its aliases are expanded"),
    ("alias inside its own node", "study: s\ngrid: {dsmc.alpha: [0.5]}\nbase: &b {model: dsmc, x: *b}\n",
     "the alias *b is inside the node it refers to"),
    ("nested 100 deep", study_text().replace("base: {", f"base: {{x: {nested(100)}, "),
     "nested more than 64 levels deep"),
    ("nested 5000 deep", study_text().replace("base: {", f"base: {{x: {nested(5000)}, "),
     "nested more than 64 levels deep"),
    ("more than 1 MiB", study_text() + "#" * (1 << 20) + "\n", "more than 1048576 bytes"),
    ("top-level key twice", study_text() + "grid: {dsmc.alpha: [0.1]}\n", "the key 'grid' is given twice (line 4)"),
    ("nested key twice", study_text().replace("alpha: 0.8", "alpha: 0.8, alpha: 0.7"), "the key 'alpha' is given twice"),
    ("grid key twice", "study: s\nbase: {model: dsmc}\ngrid: {dsmc.alpha: [0.5], dsmc.alpha: [0.6]}\n",
     "the key 'dsmc.alpha' is given twice"),
    ("NaN in a grid", study_text(grid={"dsmc.alpha": ["NANX"]}).replace("NANX", ".nan"),
     "grid.dsmc.alpha[0] = nan: a config value must be a finite number"),
    ("inf in base", study_text().replace("t_end: 2", "t_end: .inf"),
     "base.dsmc.t_end = inf: a config value must be a finite number"),
    ("a date", study_text().replace("seed: 5", "seed: 2001-12-14"),
     "base.seed = datetime.date(2001, 12, 14): a date is not a config value"),
    ("an integer of 5000 digits", study_text().replace("seed: 5", "seed: " + "9" * 5000), "not a usable YAML document"),
    ("an integer beyond 64 bits", study_text().replace("seed: 5", "seed: " + "9" * 30), "an integer beyond 64 bits"),
    ("a lone surrogate", study_text().replace("seed: 5", 'seed: "\\ud800"'), "not a valid Unicode string"),
    ("a key that is not a string", study_text().replace("seed: 5", "seed: 5, 7: x"), "the key 7 is not a non-empty string"),
    ("a name of 300 characters", study_text(name="n" * 300), "a name of 300 characters (at most 100)"),
    ("not UTF-8", study_text().encode().replace(b"study: s", b"study: s\xff"), "not UTF-8 text (byte 0xff at offset 8)"),
    ("a grid key not in the schema", study_text(grid={"dsmc.alpha": [0.5], "dsmc.bogus": [1, 2]}),
     "(dsmc.alpha=0.5, dsmc.bogus=1): dsmc.bogus: unknown key; allowed here: particles"),
    ("a value the simulator refuses", study_text(grid={"dsmc.alpha": [0.5, 1.5]}),
     "(dsmc.alpha=1.5): dsmc.alpha = 1.5: must satisfy 0 < alpha <= 1"),
    ("a tag", study_text().replace("seed: 5", "seed: !custom 5"), "not YAML (line 2): "),
]


@pytest.mark.parametrize("content, message", [b[1:] for b in BAD], ids=[b[0] for b in BAD])
def test_a_bad_study_file_is_refused_in_one_line_before_anything_is_written(tmp_path, content, message):
    path = tmp_path / "bad.yaml"
    path.write_bytes(content if isinstance(content, bytes) else content.encode("utf-8", "surrogatepass"))
    with pytest.raises(gs.StudyError) as e:
        gs.run(path, into=tmp_path, quiet=True)
    assert message in str(e.value)
    assert "\n" not in str(e.value) and len(str(e.value)) < 700 and str(path) in str(e.value)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.yaml"]


def test_the_point_limit_is_raised_by_a_keyword_and_a_flag(tmp_path):
    path = tmp_path / "s.yaml"
    path.write_text(study_text(grid={"dsmc.alpha": [0.5, 0.6, 0.7]}))
    with pytest.raises(gs.StudyError, match="the grid has 3 points, more than the limit 2"):
        gs.prepare(path, into=tmp_path, max_points=2)
    assert not (tmp_path / "studies").exists()
    folder, points = gs.prepare(path, into=tmp_path, max_points=3)
    assert len(points) == 3 and len(list((folder / "points").iterdir())) == 3
    with pytest.raises(gs.StudyError, match="max_points = 0: must be an integer >= 1"):
        gs.run(path, into=tmp_path, max_points=0)
    out = cli(tmp_path, "run", "s.yaml", "--max-points", "2")
    assert out.returncode == 2 and out.stderr.count("\n") == 1
    assert "the grid has 3 points, more than the limit 2 (raise it with --max-points N" in out.stderr
    assert gs.load_study(path, max_points=None)["study"] == "s"


def test_a_shared_part_of_base_is_fine(tmp_path):
    """Anchors and aliases within the limits are YAML like any other."""
    path = tmp_path / "s.yaml"
    path.write_text("study: s\ngrid: {dsmc.alpha: [0.5]}\nbase:\n  model: dsmc\n  seed: &five 5\n"
                    "  ensembles: *five\n  dsmc: {particles: 20, alpha: 0.8, beta: 1, kernel: &k {lambda: 1, C: 1},"
                    " t_end: 1, observe_every: 1}\n")
    (h, _, config), = gs.expand(gs.load_study(path))
    assert config["ensembles"] == 5 and gs.check_points([(h, {}, config)], path)[h].startswith("dsmc:")


def run_cli(cwd, *args, timeout=30):
    env = dict(os.environ, GRANBOLTZ_BIN=os.environ.get("GRANBOLTZ_BIN", str(gs.find_binary())))
    from test_study import ROOT

    env["PYTHONPATH"] = os.pathsep.join([str(ROOT / "src" / "python"), os.environ.get("PYTHONPATH", "")])
    import sys

    return subprocess.run([sys.executable, "-m", "granboltz.study", *args], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=timeout)


def one_line_refusal(out):
    assert out.returncode == 2, out.stderr
    assert out.stderr.count("\n") == 1 and out.stderr.startswith("granboltz.study: error: "), out.stderr
    assert "Traceback" not in out.stderr + out.stdout


def test_table_errors_are_one_line_under_python_m(tmp_path):
    """Under -m the module is __main__: its errors must still be caught as the package's StudyError."""
    one_line_refusal(run_cli(tmp_path, "table", "studies/nothing"))
    (tmp_path / "s.yaml").write_text(study_text(name="none"))
    gs.prepare(tmp_path / "s.yaml", into=tmp_path)
    out = run_cli(tmp_path, "table", "s.yaml")
    one_line_refusal(out)
    assert "4 of 4 points have no sound run" in out.stderr


@pytest.mark.parametrize("kind", ["fifo", "directory", "dangling link"])
def test_a_study_file_that_is_not_a_regular_file_is_refused_at_once(tmp_path, kind):
    path = tmp_path / "s.yaml"
    if kind == "fifo":
        os.mkfifo(path)
    elif kind == "directory":
        path.mkdir()
    else:
        path.symlink_to(tmp_path / "nowhere.yaml")
    for command in ("run", "table"):
        out = run_cli(tmp_path, command, "s.yaml", timeout=20)  # a FIFO opened for a blocking read never returns
        one_line_refusal(out)
        assert "s.yaml" in out.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.yaml"]


def test_the_command_line_refuses_an_unknown_grid_key_without_running_anything(tmp_path):
    need_binary()
    (tmp_path / "s.yaml").write_text(study_text(grid={"dsmc.alpha": [0.5, 0.6], "dsmc.bogus": [1]}))
    out = run_cli(tmp_path, "run", "s.yaml")
    one_line_refusal(out)
    assert "dsmc.bogus: unknown key" in out.stderr and "Snakemake" not in out.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.yaml"]


def test_a_path_with_a_newline_is_named_on_one_line(tmp_path):
    one_line_refusal(run_cli(tmp_path, "run", "a\nb.yaml"))
    assert "a\\nb.yaml" in run_cli(tmp_path, "table", "a\nb.yaml").stderr
