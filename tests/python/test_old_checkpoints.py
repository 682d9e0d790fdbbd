"""Checkpoints written by the build before the state archive (tests/checkpoints/, one per engine
and optional state) resume with this build and finish with every dataset identical to an
uninterrupted run of the same config. A checkpoint names the build that wrote it and granboltz
refuses another's (its policy, kept); the test relabels the copy, so that what is tested is
the stored state: names, shapes, types and the order of packed fields."""
import os
import shutil
import subprocess

import h5py
import numpy as np
import pytest

from conftest import ROOT

BINARY = os.environ.get("GRANBOLTZ_BIN", str(ROOT / "build" / "granboltz"))
FIXTURES = ROOT / "tests" / "checkpoints"


def datasets(f):
    names = []
    f.visititems(lambda name, obj: names.append(name) if isinstance(obj, h5py.Dataset) else None)
    return sorted(names)


def this_build():
    out = subprocess.run([BINARY, "--version"], capture_output=True, text=True, check=True).stdout
    version, sha = out.split()[1], out.split("(")[1].rstrip(")\n ")
    return version, sha


@pytest.mark.parametrize("name", ["plain", "shear", "gas", "swpm"])
def test_a_checkpoint_of_the_earlier_build_resumes_to_the_uninterrupted_bits(tmp_path, name):
    ckpt = tmp_path / "resumed.h5.checkpoint"
    shutil.copyfile(FIXTURES / f"{name}.checkpoint", ckpt)
    version, sha = this_build()
    with h5py.File(ckpt, "r+") as f:
        assert f.attrs["git_sha"] != sha.encode()  # written by another build indeed
        f.attrs["version"], f.attrs["git_sha"] = version.encode(), sha.encode()
        config = f.attrs["config"]
    (tmp_path / "c.yaml").write_text(config.decode() if isinstance(config, bytes) else config)
    resumed = subprocess.run([BINARY, "run", "c.yaml", "-o", "resumed.h5"], cwd=tmp_path,
                             capture_output=True, text=True, timeout=120)
    assert resumed.returncode == 0, resumed.stderr
    assert "resuming from resumed.h5.checkpoint" in resumed.stderr + resumed.stdout
    assert not ckpt.exists()
    plain = subprocess.run([BINARY, "run", "c.yaml", "-q", "-o", "plain.h5"], cwd=tmp_path,
                           capture_output=True, text=True, timeout=120)
    assert plain.returncode == 0, plain.stderr
    with h5py.File(tmp_path / "resumed.h5", "r") as a, h5py.File(tmp_path / "plain.h5", "r") as b:
        assert datasets(a) == datasets(b)
        differ = [n for n in datasets(a) if np.asarray(a[n][()]).tobytes() != np.asarray(b[n][()]).tobytes()]
        assert not differ
