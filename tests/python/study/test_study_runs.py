"""granboltz.study checks that every run is sound and is its own point's: a run copied over
another point's, a truncated run, a folder, FIFO or symbolic link in place of a run are named by
table() (one line) and moved aside and made again by `run`, with the values of the first runs;
a link is never followed out of the study folder. One runner at a time: a second is refused
while the first lives; SIGTERM to the runner stops Snakemake and the simulator; a study whose
runner, Snakemake and simulator were killed (SIGKILL) resumes without a manual unlock."""

import os
import pathlib
import shutil
import signal
import subprocess
import sys
import time

import pytest

from conftest import ROOT
from granboltz import study as gs
from test_study import BASE, BINARY, cli, need_binary, write_study


def cli_home(cwd, home, *args):
    """python -m granboltz.study ARGS from `cwd` with HOME (and its caches) at `home`."""
    env = dict(os.environ, GRANBOLTZ_BIN=BINARY, HOME=str(home),
               PYTHONPATH=os.pathsep.join([str(ROOT / "src" / "python"), os.environ.get("PYTHONPATH", "")]))
    env.pop("XDG_CACHE_HOME", None)
    return subprocess.run([sys.executable, "-m", "granboltz.study", *args], cwd=cwd, env=env, capture_output=True,
                          text=True)


# dsmc.steps is a key the nosplit scheme ignores: the simulator neither uses nor stores it, so a
# run's stored config lacks it and the run is its point's all the same.
SOUND_BASE = dict(BASE, dsmc=dict(BASE["dsmc"], steps=3))


@pytest.fixture(scope="module")
def sound(tmp_path_factory):
    """A study of four points run once (HOME an empty folder of its own): (its folder, its
    table, HOME)."""
    need_binary()
    cwd = tmp_path_factory.mktemp("sound")
    write_study(cwd / "tiny.yaml", base=SOUND_BASE)
    home = tmp_path_factory.mktemp("home")
    out = cli_home(cwd, home, "run", "tiny.yaml", "--cores", "2")
    assert out.returncode == 0, out.stdout + out.stderr
    folder = cwd / "studies" / "tiny"
    return folder, gs.Study(folder).table(), home


def test_nothing_is_written_outside_the_study_folder_not_even_in_home(sound):
    """Snakemake keeps a copy of the Snakefile in ~/.cache/snakemake unless told otherwise."""
    folder, _, home = sound
    assert not list(home.iterdir()), "written in HOME: " + ", ".join(str(p) for p in home.rglob("*"))
    assert sorted(p.name for p in folder.parent.parent.iterdir()) == ["studies", "tiny.yaml"]
    assert (folder / ".snakemake" / "cache").is_dir()


def test_a_key_the_simulator_ignores_leaves_the_runs_sound(sound, tmp_path):
    cwd, folder, _ = copy_of(sound, tmp_path)
    assert gs.Study(folder).problems() == {}
    out = cli(cwd, "run", "tiny.yaml")
    assert out.returncode == 0 and "nothing to run" in out.stdout, out.stdout + out.stderr


def copy_of(sound, tmp_path):
    folder, table, _ = sound
    shutil.copytree(folder.parent.parent, tmp_path / "cwd", symlinks=True)
    return tmp_path / "cwd", tmp_path / "cwd" / "studies" / "tiny", table


def snapshot(path):
    """Every entry under `path` (links not followed): its kind and, for files, content."""
    out = {}
    for root, dirs, files in os.walk(path):
        for name in dirs + files:
            p = pathlib.Path(root, name)
            if p.is_symlink():
                out[str(p.relative_to(path))] = ("link", os.readlink(p))
            elif p.is_file():
                out[str(p.relative_to(path))] = ("file", p.read_bytes())
            else:
                out[str(p.relative_to(path))] = ("other", None)
    return out


def test_damaged_foreign_and_irregular_runs_are_named_and_made_again(sound, tmp_path):
    cwd, folder, table = copy_of(sound, tmp_path)
    h = list(table["hash"])
    runs = folder / "runs"
    outside = tmp_path / "outside"
    outside.mkdir()
    shutil.copy(runs / f"{h[3]}.h5", outside / "real.h5")
    shutil.copy(runs / f"{h[1]}.h5", runs / f"{h[0]}.h5")       # another point's run, copied over
    with open(runs / f"{h[1]}.h5", "r+b") as f:                  # cut short
        f.truncate(os.path.getsize(runs / f"{h[1]}.h5") // 2)
    os.unlink(runs / f"{h[2]}.h5")
    (runs / f"{h[2]}.h5").mkdir()                                 # a folder
    os.unlink(runs / f"{h[3]}.h5")
    (runs / f"{h[3]}.h5").symlink_to(outside / "real.h5")       # a link out of the study, to a sound run
    before_outside = snapshot(outside)

    study = gs.Study(folder)
    with pytest.raises(gs.StudyError, match="tiny: 4 of 4 points have no sound run") as e:
        study.table()
    assert "\n" not in str(e.value) and "and 1 more" in str(e.value)
    problems = study.problems()
    assert problems[h[0]].startswith("the run of another point (its dsmc.kernel.lambda differs)")
    assert problems[h[1]].startswith("damaged: ")
    assert problems[h[2]] == "a directory, not a regular file"
    assert problems[h[3]] == "a symbolic link, not a regular file"
    out = cli(cwd, "table", "tiny.yaml")
    assert out.returncode == 2 and out.stderr.count("\n") == 1 and "Traceback" not in out.stderr

    out = cli(cwd, "run", "tiny.yaml", "--cores", "2")
    assert out.returncode == 0, out.stderr
    assert "running 4 of 4 points" in out.stdout
    assert sorted(p.name for p in (folder / "damaged").iterdir()) == sorted(f"runs-{x}.h5" for x in h)
    assert (folder / "damaged" / f"runs-{h[3]}.h5").is_symlink()
    assert snapshot(outside) == before_outside                  # the link was moved, not followed
    again = gs.Study(folder).table()
    assert again.equals(table)                                  # the same seeds give the same values
    out = cli(cwd, "run", "tiny.yaml")
    assert out.returncode == 0 and "nothing to run" in out.stdout


def test_a_fifo_in_place_of_a_run_or_a_log_does_not_block(sound, tmp_path):
    cwd, folder, table = copy_of(sound, tmp_path)
    h = table["hash"][0]
    os.unlink(folder / "runs" / f"{h}.h5")
    os.mkfifo(folder / "runs" / f"{h}.h5")
    os.unlink(folder / "logs" / f"{h}.log")
    outside = tmp_path / "outside.log"
    outside.write_text("not the study's\n")
    (folder / "logs" / f"{h}.log").symlink_to(outside)         # the simulator's log must not go there
    out = subprocess.run([sys.executable, "-c", "import granboltz.study as s, sys; "
                          f"print(s.Study({str(folder)!r}).problems())"], capture_output=True, text=True, timeout=60,
                         env=dict(os.environ, PYTHONPATH=str(ROOT / "src" / "python")))
    assert out.returncode == 0 and "a FIFO, not a regular file" in out.stdout, out.stderr
    out = cli(cwd, "run", "tiny.yaml")
    assert out.returncode == 0, out.stderr
    assert "running 1 of 4 points" in out.stdout
    assert outside.read_text() == "not the study's\n"
    assert (folder / "logs" / f"{h}.log").is_file() and not (folder / "logs" / f"{h}.log").is_symlink()
    assert gs.Study(folder).table().equals(table)


def test_an_edited_point_file_or_index_is_named(tmp_path):
    write_study(tmp_path / "s.yaml", name="edit")
    folder, points = gs.prepare(tmp_path / "s.yaml", into=tmp_path)
    h = points[0][0]
    point = folder / "points" / f"{h}.yaml"
    sound = point.read_text()
    point.write_text(sound.replace("seed: 5", "seed: 6"))
    gs.prepare(tmp_path / "s.yaml", into=tmp_path)               # a run rewrites it
    assert point.read_text() == sound and len(gs.Study(folder).points) == 4
    index = folder / "index.csv"
    index.write_text(index.read_text() + "../../etc/passwd,1,2\n")
    with pytest.raises(gs.StudyError, match="index.csv: does not list the points of .*study.yaml \\(line 6 differs\\)"):
        gs.Study(folder)
    gs.prepare(tmp_path / "s.yaml", into=tmp_path)
    lines = index.read_text().splitlines(keepends=True)
    index.write_text(lines[0] + lines[1][:15])                   # cut short in its first row
    with pytest.raises(gs.StudyError, match="line 2 differs"):
        gs.Study(folder)
    index.write_text("".join(lines[:2]))                         # cut at a line's end
    with pytest.raises(gs.StudyError, match="line 3 differs"):
        gs.Study(folder)


def test_symbolic_links_among_the_study_folders_are_refused(tmp_path):
    write_study(tmp_path / "s.yaml", name="links")
    folder, _ = gs.prepare(tmp_path / "s.yaml", into=tmp_path)
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    (folder / "runs").symlink_to(elsewhere)
    before = snapshot(tmp_path)
    with pytest.raises(gs.StudyError, match="runs: is a symbolic link, not a folder of the study"):
        gs.run(tmp_path / "s.yaml", into=tmp_path, quiet=True)
    assert snapshot(tmp_path) == before


# ------------------------------------------------------------------------------ signals and locks
LONG = dict(BASE, ensembles=1, dsmc=dict({k: v for k, v in BASE["dsmc"].items() if k != "steady_from"},
                                          particles=100000, kernel={"lambda": 0, "C": 0.0795774715459477},
                                          t_end=2000, observe_every=500))  # ~6 s: the runner must be caught running


def start_long(tmp_path, name):
    """A runner of a one-point study whose simulator runs a few seconds, once the simulator has
    started (its temporary output exists): (the runner's Popen, the study folder)."""
    need_binary()
    write_study(tmp_path / "s.yaml", grid={"dsmc.alpha": [0.5]}, name=name, base=LONG)
    env = dict(os.environ, GRANBOLTZ_BIN=BINARY,
               PYTHONPATH=os.pathsep.join([str(ROOT / "src" / "python"), os.environ.get("PYTHONPATH", "")]))
    runner = subprocess.Popen([sys.executable, "-m", "granboltz.study", "run", "s.yaml"], cwd=tmp_path, env=env,
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    folder = tmp_path / "studies" / name
    deadline = time.monotonic() + 60
    while not list((folder / "runs").glob("*.h5.tmp.*")):
        assert runner.poll() is None, runner.communicate()
        assert time.monotonic() < deadline, "the simulator did not start"
        time.sleep(0.05)
    return runner, folder


def processes_in(folder):
    """The pids of processes whose working directory is `folder` (Snakemake and the simulator)."""
    pids = []
    for p in pathlib.Path("/proc").iterdir():
        if p.name.isdigit():
            try:
                if os.readlink(p / "cwd") == str(folder):
                    pids.append(int(p.name))
            except OSError:
                pass
    return pids


def test_sigterm_to_the_runner_stops_snakemake_and_the_simulator_and_a_second_runner_is_refused(tmp_path):
    runner, folder = start_long(tmp_path, "term")
    assert processes_in(folder)
    second = cli(tmp_path, "run", "s.yaml")
    assert second.returncode == 2 and second.stderr.count("\n") == 1, second.stderr
    assert f"another `granboltz.study run` of this study, or the Snakemake it started, is running (runner pid {runner.pid})" \
        in second.stderr
    # The lock is the folder's, not the file's: a .runner.lock deleted, or replaced by a FIFO,
    # lets no second runner in (the pid is then unknown).
    for plant in (lambda p: None, os.mkfifo):
        (folder / gs.LOCK_NAME).unlink(missing_ok=True)
        plant(folder / gs.LOCK_NAME)
        again = cli(tmp_path, "run", "s.yaml")
        assert again.returncode == 2 and "is running; wait for it" in again.stderr, again.stderr
    runner.send_signal(signal.SIGTERM)
    _, err = runner.communicate(timeout=30)
    assert runner.returncode == 143, err
    assert err.splitlines()[-1].startswith("granboltz.study: stopped by SIGTERM")
    deadline = time.monotonic() + 10
    while processes_in(folder) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not processes_in(folder)
    assert not list((folder / "runs").glob("*")) if (folder / "runs").exists() else True, list((folder / "runs").glob("*"))
    out = cli(tmp_path, "run", "s.yaml")                         # resumes, no unlock needed
    assert out.returncode == 0, out.stderr
    assert not gs.Study(folder).problems()


def test_a_study_killed_with_sigkill_resumes_without_an_unlock(tmp_path):
    runner, folder = start_long(tmp_path, "kill")
    runner.kill()
    for pid in processes_in(folder):                             # Snakemake and the simulator, as kill -9 does
        os.kill(pid, signal.SIGKILL)
    runner.communicate()
    deadline = time.monotonic() + 10
    while processes_in(folder) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert list((folder / ".snakemake" / "locks").iterdir())   # Snakemake's lock is left behind
    out = cli(tmp_path, "run", "s.yaml")
    assert out.returncode == 0, out.stderr
    assert "removed the lock of a Snakemake that no longer runs" in out.stdout
    assert not gs.Study(folder).problems()
