"""Whether the run of a point of a parameter study (granboltz.study) is sound and its own: a
regular file (links are not followed), that `granboltz verify` passes, that is no single shard,
and whose stored config is the point's as the simulator resolves it (run_config)."""

import re
import stat
import subprocess

from .spec import RUNTIME_KEYS
from .safe_yaml import StudyError, file_kind, lstat, one_line


def run_difference(config, stored, where=""):
    """None when every value of the point `config` is the stored (resolved) config's value at
    that key, else the first key that differs (the simulator adds defaults; threads, shard and
    checkpoint are not stored)."""
    if isinstance(config, dict):
        if not isinstance(stored, dict):
            return where or "the config"
        for key, value in config.items():
            if not where and key in RUNTIME_KEYS:
                continue
            if key not in stored:
                return f"{where}{key}"
            found = run_difference(value, stored[key], f"{where}{key}.")
            if found:
                return found
        return None
    if isinstance(config, list):
        if not isinstance(stored, list) or len(stored) != len(config):
            return where.rstrip(".")
        for i, (a, b) in enumerate(zip(config, stored)):
            if run_difference(a, b, f"{where.rstrip('.')}[{i}]."):
                return f"{where.rstrip('.')}[{i}]"
        return None
    if isinstance(config, bool) != isinstance(stored, bool) or config != stored:
        return where.rstrip(".")
    return None


def _shard(config):
    shard = config.get("shard") if isinstance(config, dict) else None
    if isinstance(shard, dict) and isinstance(shard.get("count"), int) and shard["count"] > 1:
        return shard.get("index", 0), shard["count"]
    return None


def identity_problem(config, stored, shard, expected=None):
    """None when a run whose stored config is `stored` and whose shard is `shard` ((index,
    count) or None) is the run of the point `config`, else what is wrong, briefly. expected:
    the point's run_config (the simulator's parser's resolution of it): every value the run
    stores must be its value there (a run of an older simulator may lack keys added since);
    None (no parser at hand): every value of the point's own config must be stored."""
    where = run_difference(stored, expected) if expected is not None else run_difference(config, stored)
    if where:
        return f"the run of another point (its {one_line(where, 60)} differs)"
    if shard != _shard(config):
        return f"a shard {shard[0]}/{shard[1]}, not the whole run" if shard else "not the shard of this point"
    return None


def _file_shard(f):
    prov = f["provenance"].attrs if "provenance" in f else {}
    if "merged_from" in prov:
        return None
    raw = prov.get("shard", b"")
    index, _, count = (raw.decode() if isinstance(raw, bytes) else str(raw)).partition("/")
    return (int(index), int(count)) if index.isdigit() and count.isdigit() and int(count) > 1 else None


def stored_identity_problem(path, config, expected=None):
    """None when the output at `path` (a regular file that `granboltz verify` passed) is the run
    of the point `config` (expected: its run_config), else a short reason: read its stored
    config and shard only."""
    from ..output.io import RunReadError, open_run, read_config

    try:
        with open_run(path) as f:
            stored = read_config(f, path)
            shard = _file_shard(f)
    except (RunReadError, OSError, ValueError, KeyError) as e:
        return f"damaged: {brief(e, path)}"
    return identity_problem(config, stored, shard, expected)


def brief(error, path):
    """The error on one line of at most 100 characters, the path replaced by 'the file'."""
    text = " ".join(str(error).split()).replace(f"{path}: ", "").replace(str(path), "the file")
    return one_line(text, 100)


def not_regular(path):
    """None for a regular file (not followed), "missing", or what is there instead."""
    st = lstat(path)
    if st is None:
        return "missing"
    return None if stat.S_ISREG(st.st_mode) else f"{file_kind(st.st_mode)}, not a regular file"


def verify_runs(folder, hashes, binary):
    """{hash: problem} for the runs/<hash>.h5 (regular files) that `granboltz verify` does not pass."""
    problems = {}
    names = [f"{h}.h5" for h in hashes]
    line = re.compile(r"granboltz: error: ([0-9a-f]{12})\.h5: (?:damaged: )?(.*)")
    for start in range(0, len(names), 500):
        batch = names[start:start + 500]
        try:
            out = subprocess.run([binary, "verify", *batch], cwd=folder / "runs", capture_output=True, text=True,
                                 errors="replace")
        except OSError as e:
            raise StudyError(f"{binary}: cannot run granboltz verify ({e.strerror or e})") from None
        ok = {ln.split(":", 1)[0][:-3] for ln in out.stdout.splitlines() if re.fullmatch(r"[0-9a-f]{12}\.h5: ok.*", ln)}
        said = {m.group(1): m.group(2) for m in map(line.fullmatch, out.stderr.splitlines()) if m}
        for name in batch:
            h = name[:-3]
            if h not in ok:
                problems[h] = "damaged: " + one_line(said.get(h, f"granboltz verify exited {out.returncode}"), 100)
    return problems


def check_runs(folder, points, binary, expected=None):
    """{hash: problem} of the points whose run is missing, not a regular file, damaged (granboltz
    verify) or of another point (its stored config; expected: {hash: run_config})."""
    problems, present = {}, []
    for h, _, _ in points:
        problem = not_regular(folder / "runs" / f"{h}.h5")
        if problem:
            problems[h] = problem
        else:
            present.append(h)
    if present:
        problems.update(verify_runs(folder, present, binary))
    configs = {h: config for h, _, config in points}
    for h in present:
        if h not in problems:
            problem = stored_identity_problem(folder / "runs" / f"{h}.h5", configs[h], (expected or {}).get(h))
            if problem:
                problems[h] = problem
    return problems
