"""The study family of the mutation fuzzer (fuzz.py --families study; tests/fuzz/README.md).

Parameter studies (`python -m granboltz.study run|table`) given damaged study files and damaged
study folders. Case k of seed s draws from random.Random("s:k") alone:

  file    a study file of a tiny base config: grids of random sizes, keys (the schema's and
          others) and values (NaN, inf, huge, strings, dates, tags, lists, ...), base keys
          deleted or changed, alias bombs, recursive aliases, deep nesting, keys given twice,
          bad names, non-UTF-8 bytes, truncation, more than 1 MiB; or a FIFO, a folder or a
          dangling link in its place; given to run (sometimes with --max-points) or table;
  folder  a sound study of three points, run once per session and copied, then damaged: runs
          truncated, flipped, copied over or swapped with another point's, replaced by a folder,
          a FIFO or a link (out of the study, to a sound run), temporary files, a stale Snakemake
          lock, a runner lock held by a living process, point files and the index edited, the
          study's folders replaced by links, given to run or table.

The oracle: the command ends within TIMEOUT s with exit status 0 or 2 (1 only for a file case
whose points are sound configs the simulator fails at run time, with the runner's last line
saying so), no traceback; a refusal (2) is one line `granboltz.study: error: ...` and changes
nothing in the case's folder. Nothing is written outside the study folder (the case's HOME and
TMPDIR included; links planted in the study lead to files outside, which must stay as they
were). A table that succeeds is the sound study's table, exactly (a folder case) or has a row
per point (a file case); a run that succeeds leaves runs whose stored config is their point's
as `granboltz validate` resolves it, and (a folder case) a table exactly the sound study's, since a point run again
with its seed gives the same bits.
"""

import copy
import csv
import fcntl
import hashlib
import io
import json
import os
import pathlib
import random
import re
import resource
import shutil
import signal
import subprocess
import sys
import tempfile
import time

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parents[1]
PYTHON = "/usr/bin/python3" if os.access("/usr/bin/python3", os.X_OK) else sys.executable
TIMEOUT = 90.0  # a run case starts Snakemake (a few seconds) and may run a few tiny points
NAME = "fz"
BASE = {"model": "dsmc", "seed": 3, "ensembles": 2,
        "dsmc": {"particles": 20, "alpha": 0.8, "beta": 1, "kernel": {"lambda": 0, "C": 0.0795774715459477},
                 "t_end": 0.5, "observe_every": 0.25}}
GRID = {"dsmc.alpha": [0.5, 0.7, 0.9]}

# Grid keys: cheap ones of the schema, and others (unknown, through a value, malformed).
KEYS = ["dsmc.alpha", "dsmc.alpha", "seed", "seed", "dsmc.kernel.lambda", "ensembles", "dsmc.beta", "dsmc.t_end",
        "dsmc.particles", "dsmc.observe_every", "threads", "dsmc.scheme", "dsmc.kernel", "dsmc",
        "dsmc.bogus", "bogus", "dsmc.kernel.lambda.x", "seed.x", "dsmc..alpha", ".seed", "seed.", "x" * 300,
        "dsmc.alpha ", "dsmc.é", "dsmc.\u202ealpha", "a.b.c.d.e.f", "model", "dsmc.steady_from", "checkpoint.every_seconds"]
# Values as YAML text: sound ones for the cheap keys, and everything else.
SOUND = ["0.5", "0.6", "0.9", "1", "1.0", "0", "2", "3", "0.25", "nosplit", "euler"]
ODD = [".nan", ".NaN", ".inf", "-.inf", "+.inf", "1.0e+309", "-1.0e+309", "1e309", "5e-324", "4.9e-324",
       "2.2250738585072014e-308", "1.7976931348623157e+308", "-0.0", "-1", "1.5", "1e-300", "0x10", "0o17", "1_000",
       "9" * 20, "9" * 400, "9" * 5000, "-" + "9" * 30, "18446744073709551616", "9007199254740993",
       "''", "'0.5'", '"1"', "x" * 3000, "\"\\u0000\"", "\"\\ud800\"", "\"\\x1b[31m\"", "é", "😀", "\"line\\nline\"",
       "true", "false", "yes", "null", "~", "2001-12-14", "2001-12-14t21:59:43.10-05:00", "12:30:00",
       "[]", "{}", "[1, 2]", "{a: 1}", "[[[[1]]]]", "{lambda: 0, C: 1}", "!!binary aGVsbG8=", "!!set {a, b}",
       "!!omap [a: 1]", "!!python/object/apply:os.system ['true']", "!custom 1", "!!str 1", "!!float 1", "!!int 1",
       "*undefined", "&v 1", "<<", "? a"]
# Sound values of some keys, odd ones included (huge seeds, tiny t_end, mappings as grid values):
# a grid of these runs (a few tiny points), so that the run, the checks of its runs and the table
# meet unusual values too.
VALID = {"dsmc.alpha": ["0.5", "0.9", "1", "1.0", "1.0e-300", "0.1"],
         "seed": ["0", "1", "18446744073709551615", "9007199254740993", "12345678901234567890"],
         "ensembles": ["1", "2", "3"], "dsmc.particles": ["2", "3", "20", "31"],
         "dsmc.kernel.lambda": ["0", "1", "2", "0.5"], "dsmc.kernel": ["{lambda: 0, C: 0.1}", "{lambda: 1, C: 0.05}"],
         "dsmc.t_end": ["0.25", "0.5", "1.0e-9"], "dsmc.beta": ["0", "1", "0.5"], "dsmc.scheme": ["nosplit", "euler"],
         "dsmc.observe_every": ["0.25", "0.5"], "threads": ["0", "1", "2"],
         "dsmc.initial": ["{temperature: 2}", "{temperature: 0.5}"], "dsmc.steady_from": ["0.25"],
         "dsmc.histogram": ["{shells: 4, radius: 3}"], "dsmc.steps": ["2", "3"]}
NAMES = [NAME] * 12 + ["", "a b", "a/b", "..", ".", "-", "n" * 100, "n" * 101, "n" * 300, "é", "a\tb", "null", "1",
                       "[a]", "{a: 1}", "'fz'", "\"fz\"", "!!str fz", "fz\u202e", "CON", "-rf"]


# ------------------------------------------------------------------------------------------ file cases
def yaml_dump(value):
    import yaml

    return yaml.safe_dump(value, default_flow_style=False, sort_keys=False, width=10 ** 6)


def indent(text, n=2):
    return "\n".join(" " * n + line if line else line for line in text.splitlines())


def mutate_base(rng, base, notes):
    """A key of the base config deleted, changed to an odd value or added."""
    paths = []

    def walk(node, prefix):
        for k, v in node.items():
            paths.append(prefix + [k])
            if isinstance(v, dict):
                walk(v, prefix + [k])
    walk(base, [])
    path = rng.choice(paths)
    parent = base
    for k in path[:-1]:
        parent = parent[k]
    op = rng.choice(["delete", "change", "add"])
    if op == "delete":
        del parent[path[-1]]
    elif op == "change":
        parent[path[-1]] = rng.choice([None, True, -1, 0, 1.5, 1e300, "x", [], {}, [1], {"a": 1}, 10 ** 30])
    else:
        parent[rng.choice(["bogus", "x" * 200, "seed2", "Alpha", "1"])] = rng.choice([1, "x", None, [1]])
    notes.append(f"base {op} {'.'.join(map(str, path))}")


def valid_grid_lines(rng, notes):
    """A grid of sound values (most of the time): one to three keys, at most four points."""
    keys = rng.sample(sorted(VALID), rng.choice([1, 1, 2, 3]))
    lines, count = [], 1
    for key in keys:
        size = 1 if count >= 2 else rng.choice([1, 2])
        lines.append(f"  {key}: [{', '.join(rng.sample(VALID[key], min(size, len(VALID[key]))))}]")
        count *= size
    notes.append(f"sound grid {', '.join(keys)}")
    return lines, count


def grid_lines(rng, notes):
    """The grid as YAML lines and its number of points (None when the text is odd)."""
    if rng.random() < 0.35:
        return valid_grid_lines(rng, notes)
    n_keys = rng.choice([1, 1, 1, 2, 2, 3, 4, 6, 8])
    keys = rng.sample(KEYS, n_keys) if rng.random() < 0.5 else [rng.choice(KEYS[:10]) for _ in range(n_keys)]
    lines, count = [], 1
    for key in keys:
        size = rng.choice([1, 1, 2, 2, 3, 4, 10, 30, 100, 1000]) if rng.random() < 0.9 else rng.choice([0, 5000, 20000])
        if size > 50:  # a long list: numbers, mostly distinct
            values = [repr(rng.uniform(0, 1)) for _ in range(size)]
        else:
            values = [rng.choice(SOUND) if rng.random() < 0.7 else rng.choice(ODD) for _ in range(size)]
        count *= max(size, 1)
        key_text = key if re.fullmatch(r"[A-Za-z0-9_.]+", key) else json.dumps(key)
        style = rng.random()
        if style < 0.8:
            lines.append(f"  {key_text}: [{', '.join(values)}]")
        elif style < 0.9:
            lines.append(f"  {key_text}:")
            lines += [f"    - {v}" for v in values]
        else:
            lines.append(f"  {key_text}: {rng.choice(['0.5', 'x', '~', '{}', '[]', '[[0.5]]'])}")
    notes.append(f"grid {n_keys} keys, {count} points")
    return lines, count


def bomb_lines(rng):
    depth, width = rng.randint(3, 9), rng.randint(2, 10)
    lines = ["    a0: &a0 [lol, lol]"]
    for d in range(1, depth):
        lines.append(f"    a{d}: &a{d} [" + ", ".join([f"*a{d - 1}"] * width) + "]")
    return lines, f"alias bomb {width}^{depth}"


def nested(depth, rng):
    if rng.random() < 0.5:
        return "[" * depth + "1" + "]" * depth
    return "{a: " * depth + "1" + "}" * depth


def text_mutation(rng, lines):
    """A damage of the study file's text: returns (lines or bytes, note)."""
    op = rng.choice(["bomb", "recursive", "deep", "twice", "twice_nested", "big", "bytes", "truncate", "unknown",
                     "document", "tabs", "anchor", "flip", "empty", "bom", "merge"])
    if "base:" not in lines and op in ("bomb", "deep", "merge"):
        op = "unknown"
    if op == "bomb":
        bomb, note = bomb_lines(rng)
        i = lines.index("base:") + 1
        return lines[:i] + ["  x:"] + bomb + lines[i:], note
    if op == "recursive":  # base holds an alias of itself
        if "base:" not in lines or "grid:" not in lines:
            return lines, op
        b, g = lines.index("base:"), lines.index("grid:")
        return lines[:b] + ["base: &b"] + lines[b + 1:g] + ["  self: *b"] + lines[g:], op
    if op == "deep":
        depth = rng.choice([30, 63, 64, 65, 100, 400, 1000, 5000])
        i = lines.index("base:") + 1
        return lines[:i] + [f"  deep: {nested(depth, rng)}"] + lines[i:], f"deep {depth}"
    if op == "twice":
        top = [i for i, line in enumerate(lines) if line and not line.startswith(" ")]
        i = rng.choice(top)
        return lines + [lines[i] if not lines[i].endswith(":") else lines[i] + " {}"], op
    if op == "twice_nested":
        inner = [i for i, line in enumerate(lines) if line.startswith("  ") and not line.startswith("   ")]
        if inner:
            i = rng.choice(inner)
            return lines[:i + 1] + [lines[i]] + lines[i + 1:], op
        return lines, op
    if op == "big":
        return lines + ["#" + "x" * (1 << 20)], op
    if op == "bytes":
        data = "\n".join(lines).encode()
        i = rng.randrange(len(data) + 1)
        junk = bytes(rng.choice([0x80, 0xC3, 0xFF, 0xFE, 0xED, 0xA0, 0x00, 0x1B]) for _ in range(rng.randint(1, 4)))
        return data[:i] + junk + data[i:], op
    if op == "truncate":
        data = "\n".join(lines)
        return data[:rng.randrange(len(data) + 1)], op
    if op == "unknown":
        return lines + [rng.choice(["seeds: [1]", "studies: x", "Grid: {}", "'study ': x", "1: 2"])], op
    if op == "document":
        return lines + ["---", "study: other"], op
    if op == "tabs":
        i = rng.randrange(len(lines))
        return lines[:i] + ["\t" + lines[i]] + lines[i + 1:], op
    if op == "anchor":
        return [line.replace("seed: 3", "seed: &s 3", 1) for line in lines] + ["  dup: *s"] \
            if any("seed: 3" in line for line in lines) else lines, op
    if op == "flip":
        data = bytearray("\n".join(lines).encode())
        i = rng.randrange(len(data))
        data[i] ^= 1 << rng.randrange(7)  # ASCII stays ASCII: YAML damage, not encoding damage
        return bytes(data), op
    if op == "empty":
        return [], op
    if op == "bom":
        return ["\ufeff" + lines[0]] + lines[1:], op
    # merge keys within base
    i = lines.index("base:") + 1
    return lines[:i] + ["  m: &m {seed: 9}", "  <<: *m"] + lines[i:], op


def file_case(rng):
    notes = []
    base = copy.deepcopy(BASE)
    if rng.random() < 0.2:
        mutate_base(rng, base, notes)
    name = rng.choice(NAMES)
    name_text = name if re.fullmatch(r"[A-Za-z0-9_-]+", name) or rng.random() < 0.3 else json.dumps(name)
    glines, count = grid_lines(rng, notes)
    lines = [f"study: {name_text}", "base:", indent(yaml_dump(base)), "grid:"] + glines
    lines = "\n".join(lines).split("\n")
    text = None
    for _ in range(rng.choice([0, 0, 0, 1, 1, 2])):
        out, note = text_mutation(rng, lines if isinstance(lines, list) else lines.splitlines())
        notes.append(note)
        if isinstance(out, bytes):
            text = out.decode("utf-8", "surrogateescape")
            break
        lines = out if isinstance(out, list) else out.split("\n")
    if text is None:
        text = "\n".join(lines) + "\n"
    special = None
    if rng.random() < 0.06:
        special = rng.choice(["fifo", "directory", "dangling", "device", "unreadable"])
        notes.append(f"study file: {special}")
    command = "run" if rng.random() < 0.8 else "table"
    args = []
    if command == "run" and count > 6 and rng.random() < 0.7:
        args = ["--max-points", str(rng.randint(1, max(1, min(count - 1, 10 ** 6))))]
    elif command == "run" and rng.random() < 0.05:
        args = ["--max-points", str(rng.choice([1, 2, 3, 10 ** 5]))]
    if command == "table" and rng.random() < 0.5:
        args = ["--csv"]
    if command == "run" and count > 6 and not args:
        # a grid that could pass would run many points: make one of its values refused
        text = text.replace("grid:\n", "grid:\n  dsmc.kernel.lambda: [0, -3]\n", 1)
        notes.append("a refused value")
    return {"family": "study", "command": command, "kind": "file", "study": text, "special": special,
            "args": args, "folder": [], "note": "; ".join(notes)}


# ------------------------------------------------------------------------------------------ folder cases
RUN_DAMAGE = ["truncate", "flip", "copy", "swap", "directory", "fifo", "link_outside", "link_nowhere", "link_dir",
              "delete", "empty", "junk", "config_attr", "shard_attr"]
OTHER_DAMAGE = ["stale_lock", "held_lock", "tmp", "incomplete", "point_edit", "point_delete", "point_fifo",
                "point_link", "index_row", "index_truncate", "index_bytes", "index_fifo", "index_delete", "log_link",
                "log_fifo", "log_dir", "part_link", "part_file", "runner_lock_fifo", "runner_lock_dir",
                "runner_lock_link", "study_yaml", "damaged_link", "metadata_link"]


def folder_case(rng):
    damage = []
    for _ in range(rng.choice([1, 1, 1, 2, 2, 3])):
        op = rng.choice(RUN_DAMAGE * 2 + OTHER_DAMAGE)
        d = {"op": op, "point": rng.randrange(3)}
        if op == "truncate":
            d["fraction"] = rng.random()
        elif op == "flip":
            d["fraction"], d["bit"] = rng.random(), rng.randrange(8)
        elif op in ("copy", "swap"):
            d["other"] = (d["point"] + rng.randrange(1, 3)) % 3
        elif op == "tmp":
            d["size"] = rng.choice([0, 100, 5000])
        elif op in ("part_link", "part_file"):
            d["part"] = rng.choice(["runs", "points", "logs", ".snakemake", "damaged"])
        elif op == "stale_lock":
            d["names"] = rng.choice([["0.input.lock"], ["0.output.lock"], ["0.input.lock", "0.output.lock"], ["x"]])
        damage.append(d)
    command = rng.choice(["run", "run", "table"])
    args = ["--csv"] if command == "table" else rng.choice([[], [], ["--cores", "2"]])
    return {"family": "study", "command": command, "kind": "folder", "study": None, "special": None, "args": args,
            "folder": damage, "note": ", ".join(d["op"] for d in damage)}


def study_case(rng):
    return file_case(rng) if rng.random() < 0.55 else folder_case(rng)


# ------------------------------------------------------------------------------------------ running
def snapshot(path):
    """Every entry under `path`, links not followed: kind and content digest (or link target)."""
    out = {}
    path = pathlib.Path(path)
    for root, dirs, files in os.walk(path):
        for name in dirs + files:
            p = pathlib.Path(root, name)
            rel = str(p.relative_to(path))
            st = os.lstat(p)
            if os.path.islink(p):
                out[rel] = "link:" + os.readlink(p)
            elif p.is_file() and not p.is_symlink():
                try:
                    out[rel] = hashlib.sha256(p.read_bytes()).hexdigest()
                except OSError:
                    out[rel] = "unreadable"
            else:
                out[rel] = f"mode:{st.st_mode:o}"
    return out


def session_processes(sid):
    pids = []
    for p in pathlib.Path("/proc").iterdir():
        if p.name.isdigit():
            try:
                fields = (p / "stat").read_text().rsplit(")", 1)[1].split()
            except OSError:
                continue
            if int(fields[3]) == sid:
                pids.append(int(p.name))
    return pids


def run_study(args, cwd, env, timeout=TIMEOUT):
    """python -m granboltz.study ARGS in a session of its own (Snakemake makes a process group
    of its own inside it): on the timeout every process of the session is killed."""
    def apply():
        os.setsid()
        resource.setrlimit(resource.RLIMIT_FSIZE, (200 << 20, 200 << 20))
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
    start = time.monotonic()
    p = subprocess.Popen([PYTHON, "-m", "granboltz.study", *args], cwd=cwd, env=env, stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, stdin=subprocess.DEVNULL, preexec_fn=apply)
    try:
        out, err = p.communicate(timeout=timeout)
        timed_out = False
    except subprocess.TimeoutExpired:
        for pid in session_processes(p.pid):
            try:
                os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
        out, err = p.communicate()
        timed_out = True
    for pid in session_processes(p.pid):  # nothing of it may outlive it
        timed_out = timed_out or "left running"
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    return {"rc": p.returncode, "stdout": out.decode("utf-8", "replace"), "stderr": err.decode("utf-8", "replace"),
            "timed_out": timed_out, "seconds": time.monotonic() - start}


class Template:
    """The sound study of the folder cases, run once per session: its folder, study text, table."""

    def __init__(self, binary):
        self.dir = pathlib.Path(tempfile.mkdtemp(prefix="granboltz-fuzz-study-"))
        import yaml

        self.text = yaml.safe_dump({"study": NAME, "base": BASE, "grid": GRID}, sort_keys=False)
        (self.dir / "s.yaml").write_text(self.text)
        env = environment(binary, self.dir)
        r = run_study(["run", "s.yaml"], self.dir, env)
        if r["rc"] != 0:
            raise SystemExit(f"fuzz: the sound study does not run: {r['stderr'][-500:]}")
        t = run_study(["table", "s.yaml", "--csv"], self.dir, env)
        if t["rc"] != 0:
            raise SystemExit(f"fuzz: the sound study's table fails: {t['stderr'][-500:]}")
        self.table = t["stdout"]
        self.folder = self.dir / "studies" / NAME
        self.hashes = [row[0] for row in csv.reader(io.StringIO((self.folder / "index.csv").read_text()))][1:]

    def cleanup(self):
        shutil.rmtree(self.dir, ignore_errors=True)


_TEMPLATES = {}


def template(binary):
    if binary not in _TEMPLATES:
        _TEMPLATES[binary] = Template(binary)
        import atexit

        atexit.register(_TEMPLATES[binary].cleanup)
    return _TEMPLATES[binary]


def environment(binary, d):
    home = pathlib.Path(d) / ".home"
    tmp = pathlib.Path(d) / ".tmp"
    home.mkdir(exist_ok=True)
    tmp.mkdir(exist_ok=True)
    return {"PATH": os.environ.get("PATH", "/usr/bin:/bin"), "HOME": str(home), "TMPDIR": str(tmp),
            "GRANBOLTZ_BIN": binary, "PYTHONPATH": str(ROOT / "src" / "python"), "LANG": "C.UTF-8"}


def place_study_file(d, case):
    path = d / "s.yaml"
    special = case.get("special")
    if special == "fifo":
        os.mkfifo(path)
    elif special == "directory":
        path.mkdir()
        (path / "x.yaml").write_text("study: x\n")
    elif special == "dangling":
        path.symlink_to(d / "nowhere.yaml")
    elif special == "device":
        path.symlink_to("/dev/zero")
    else:
        path.write_bytes(case["study"].encode("utf-8", "surrogateescape"))
        if special == "unreadable":
            path.chmod(0)
    return path


def damage_folder(d, folder, hashes, damage, outside):
    """Apply the folder damage; returns a held lock's file descriptor, if one is held."""
    held = None
    for m in damage:
        h = hashes[m["point"]]
        run = folder / "runs" / f"{h}.h5"
        op = m["op"]

        def clear(p):
            if p.is_symlink() or p.is_file() or p.is_fifo():
                p.unlink()
            elif p.is_dir():
                shutil.rmtree(p)
        if op == "truncate" and run.is_file() and not run.is_symlink():
            with open(run, "r+b") as f:
                f.truncate(int(os.path.getsize(run) * m["fraction"]))
        elif op == "flip" and run.is_file() and not run.is_symlink():
            data = bytearray(run.read_bytes())
            if data:
                data[int(len(data) * m["fraction"]) % len(data)] ^= 1 << m["bit"]
                run.write_bytes(bytes(data))
        elif op == "copy":
            other = folder / "runs" / f"{hashes[m['other']]}.h5"
            if other.is_file():
                clear(run)
                shutil.copy(other, run)
        elif op == "swap":
            other = folder / "runs" / f"{hashes[m['other']]}.h5"
            if run.exists() and other.exists():
                tmp = run.with_name("swap.tmp")
                os.rename(run, tmp)
                os.rename(other, run)
                os.rename(tmp, other)
        elif op in ("config_attr", "shard_attr") and run.is_file() and not run.is_symlink():
            import h5py  # attributes are outside the datasets' checksums: edited, the file verifies

            try:
                with h5py.File(run, "r+") as f:
                    if op == "config_attr":
                        raw = f.attrs["config"]
                        text = raw.decode() if isinstance(raw, bytes) else str(raw)
                        f.attrs["config"] = re.sub(r"alpha: [0-9.]+", "alpha: 0.6", text, count=1)
                    else:
                        f["provenance"].attrs["shard"] = "0/2"
            except (OSError, KeyError):
                pass  # damaged already by an earlier operation
        elif op == "directory":
            clear(run)
            run.mkdir()
            (run / "inside.h5").write_bytes(b"x")
        elif op == "fifo":
            clear(run)
            os.mkfifo(run)
        elif op == "link_outside":
            clear(run)
            run.symlink_to(outside / "real.h5")
        elif op == "link_nowhere":
            clear(run)
            run.symlink_to(outside / "nowhere.h5")
        elif op == "link_dir":
            clear(run)
            run.symlink_to(outside)
        elif op == "delete":
            clear(run)
        elif op == "empty":
            clear(run)
            run.write_bytes(b"")
        elif op == "junk":
            clear(run)
            run.write_bytes(b"\x89HDF\r\n\x1a\n" + bytes(range(256)) * 8)
        elif op == "stale_lock":
            locks = folder / ".snakemake" / "locks"
            locks.mkdir(parents=True, exist_ok=True)
            for name in m["names"]:
                (locks / name).write_text(f"{folder}/runs/{h}.h5\n")
        elif op == "held_lock":  # another runner: it holds the folder's flock and wrote its pid
            path = folder / ".runner.lock"
            if path.is_file() and not path.is_symlink() and held is None:
                held = os.open(folder, os.O_RDONLY | os.O_DIRECTORY)
                fcntl.flock(held, fcntl.LOCK_EX)
                path.write_bytes(b"999999\n")
        elif op == "tmp":
            (folder / "runs").mkdir(exist_ok=True)
            (folder / "runs" / f"{h}.h5.tmp.4194303.AbCdEf").write_bytes(b"\0" * m["size"])
        elif op == "incomplete":
            inc = folder / ".snakemake" / "incomplete"
            inc.mkdir(parents=True, exist_ok=True)
            import base64

            (inc / base64.b64encode(f"runs/{h}.h5".encode()).decode()).write_text("")
        elif op.startswith("point_"):
            p = folder / "points" / f"{h}.yaml"
            if op == "point_edit" and p.is_file():
                p.write_text(p.read_text().replace("seed: 3", "seed: 4"))
            elif op == "point_delete":
                clear(p)
            elif op == "point_fifo":
                clear(p)
                os.mkfifo(p)
            elif op == "point_link":
                clear(p)
                p.symlink_to(outside / "text.txt")
        elif op.startswith("index_"):
            p = folder / "index.csv"
            if op == "index_row" and p.is_file():
                p.write_text(p.read_text() + rng_row(m["point"]))
            elif op == "index_truncate" and p.is_file():
                p.write_bytes(p.read_bytes()[:m["point"] * 13 + 5])
            elif op == "index_bytes" and p.is_file():
                p.write_bytes(p.read_bytes() + b"\xff\xfe\n")
            elif op == "index_fifo":
                clear(p)
                os.mkfifo(p)
            elif op == "index_delete":
                clear(p)
        elif op.startswith("log_"):
            p = folder / "logs" / f"{h}.log"
            clear(p)
            if op == "log_link":
                p.symlink_to(outside / "text.txt")
            elif op == "log_fifo":
                os.mkfifo(p)
            else:
                p.mkdir()
        elif op in ("part_link", "part_file", "damaged_link", "metadata_link"):
            part = {"damaged_link": "damaged", "metadata_link": ".snakemake/metadata"}.get(op, m.get("part"))
            p = folder / part
            if p.exists() or p.is_symlink():
                if op != "part_file" and p.is_dir() and not p.is_symlink():
                    shutil.copytree(p, outside / f"copy-{part.replace('/', '-')}", symlinks=True, dirs_exist_ok=True)
                clear(p)
            if op == "part_file":
                p.write_text("not a folder\n")
            else:
                (outside / f"copy-{part.replace('/', '-')}").mkdir(exist_ok=True)
                p.symlink_to(outside / f"copy-{part.replace('/', '-')}")
        elif op.startswith("runner_lock_"):
            p = folder / ".runner.lock"
            clear(p)
            if op == "runner_lock_fifo":
                os.mkfifo(p)
            elif op == "runner_lock_dir":
                p.mkdir()
            else:
                p.symlink_to(outside / "text.txt")
        elif op == "study_yaml":
            p = folder / "study.yaml"
            clear(p)
            os.mkfifo(p)
    return held


def rng_row(i):
    return ["../../outside/x,0.5\n", "000000000000,0.5\n", "zz,1,2,3\n"][i]


def refusal_problem(r):
    """None if a refusal is one line `granboltz.study: error: ...`, else what is wrong."""
    lines = r["stderr"].splitlines()
    if len(lines) != 1 or not lines[0].startswith("granboltz.study: error: "):
        return f"a refusal of {len(lines)} lines: {' | '.join(lines[:3])[:300]}"
    if len(lines[0]) > 1200:
        return f"a refusal of {len(lines[0])} characters"
    return None


def outcome_problem(case, r):
    if r["timed_out"] == "left running":
        return "processes of the command outlived it"
    if r["timed_out"]:
        return f"did not finish within {TIMEOUT:.0f} s"
    text = r["stdout"] + r["stderr"]
    if "Traceback (most recent call last)" in text:
        last = [ln for ln in r["stderr"].splitlines() if ln.strip()][-1:] or [""]
        return f"traceback: {last[0][:200]}"
    if r["rc"] == 2:
        return refusal_problem(r)
    if r["rc"] == 1 and case["kind"] == "file" and case["command"] == "run" and \
            r["stderr"].rstrip().splitlines()[-1].startswith("granboltz.study: error: Snakemake failed"):
        return None  # sound configs the simulator fails at run time (exit 1 is documented)
    if r["rc"] != 0:
        return f"exit status {r['rc']}: {(r['stderr'].strip().splitlines() or [''])[-1][:200]}"
    return None


def runs_belong(folder, binary):
    """None when every point of the index has a run whose stored config is its point's as
    `granboltz validate` resolves it (checked here with the simulator's command line, h5py and
    PyYAML, not with the package's own check): every stored value is the resolved one."""
    import h5py
    import yaml

    rows = list(csv.reader(io.StringIO((folder / "index.csv").read_text(), newline="")))
    for row in rows[1:]:
        h = row[0]
        v = subprocess.run([binary, "validate", str(folder / "points" / f"{h}.yaml")], capture_output=True, text=True)
        if v.returncode != 0:
            return f"point {h} of a successful run is refused by granboltz validate: {v.stderr.strip()[:150]}"
        resolved = yaml.safe_load(v.stdout)
        run = folder / "runs" / f"{h}.h5"
        if run.is_symlink() or not run.is_file():
            return f"run {h} is not a regular file after a successful run"
        with h5py.File(run, "r") as f:
            raw = f.attrs["config"]
            stored = yaml.safe_load(raw.decode() if isinstance(raw, bytes) else raw)

        def within(a, b):  # every value of a is b's
            if isinstance(a, dict):
                return isinstance(b, dict) and all(k in b and within(v, b[k]) for k, v in a.items())
            if isinstance(a, list):
                return isinstance(b, list) and len(a) == len(b) and all(map(within, a, b))
            return isinstance(a, bool) == isinstance(b, bool) and a == b
        if not within(stored, resolved):
            return f"run {h} after a successful run is not its point's"
    return None


def run_case(fz, case):
    """Run one study case; None (passed) or what broke the oracle."""
    binary = fz.binary
    d = pathlib.Path(tempfile.mkdtemp(prefix="granboltz-fuzz-study-case-"))
    held = None
    try:
        env = environment(binary, d)
        outside = d / "outside"
        outside.mkdir()
        (outside / "text.txt").write_text("outside the study\n")
        if case["kind"] == "folder":
            t = template(binary)
            shutil.copytree(t.folder, d / "studies" / NAME, symlinks=True)
            (d / "s.yaml").write_text(t.text)
            shutil.copy(t.folder / "runs" / f"{t.hashes[0]}.h5", outside / "real.h5")
            held = damage_folder(d, d / "studies" / NAME, t.hashes, case["folder"], outside)
        else:
            place_study_file(d, case)
        before = snapshot(d)
        args = [case["command"], "s.yaml", *case["args"]]
        r = run_study(args, d, env)
        if fz.verbose:
            last = (r["stderr"].strip().splitlines() or [""])[-1]
            print(f"    study {' '.join(args)[:60]} -> {r['rc']} {r['seconds']:.1f}s {last[:150]}")
        problem = outcome_problem(case, r)
        if problem:
            return problem
        after = snapshot(d)
        if r["rc"] == 2 or case["command"] == "table":
            if after != before:
                changed = sorted(set(after) ^ set(before) | {k for k in after if k in before and after[k] != before[k]})
                return f"a {'refusal' if r['rc'] == 2 else 'table'} changed the folder: {changed[:4]}"
        else:
            name = NAME if case["kind"] == "folder" else study_name(case)
            inside = f"studies/{name}/" if name else None
            changed = sorted(k for k in set(after) | set(before)
                             if after.get(k) != before.get(k) and k not in ("studies", f"studies/{name}")
                             and not (inside and k.startswith(inside)))
            if changed:
                return f"written outside the study folder: {changed[:4]}"
        if held is not None and case["command"] == "run" and r["rc"] != 2:
            return "a run went ahead while another runner held the study's lock"
        if r["rc"] == 0 and case["kind"] == "folder":
            table = r["stdout"] if case["command"] == "table" else None
            if table is None:
                if held is not None:
                    os.close(held)
                    held = None
                problem = runs_belong(d / "studies" / NAME, binary)
                if problem:
                    return problem
                t = run_study(["table", "s.yaml", "--csv"], d, env)
                if t["rc"] != 0:
                    return f"the table after a successful run fails: {(t['stderr'].strip().splitlines() or [''])[-1][:200]}"
                table = t["stdout"]
            if table != template(binary).table:
                return "a table other than the sound study's"
        if r["rc"] == 0 and case["kind"] == "file" and case["command"] == "run":
            folder = d / "studies" / study_name(case)
            problem = runs_belong(folder, binary)
            if problem:
                return problem
            t = run_study(["table", "s.yaml", "--csv"], d, env)
            if t["rc"] != 0:
                return f"the table after a successful run fails: {(t['stderr'].strip().splitlines() or [''])[-1][:200]}"
            rows = list(csv.reader(io.StringIO(t["stdout"])))
            if len(rows) != len(list(csv.reader(io.StringIO((folder / "index.csv").read_text(), newline="")))):
                return "the table after a successful run has another number of rows than the index"
        return None
    finally:
        if held is not None:
            os.close(held)
        for root, dirs, files in os.walk(d):  # an unreadable study file or folder is removable again
            for name in dirs:
                p = os.path.join(root, name)
                if not os.path.islink(p):
                    os.chmod(p, 0o755)
        shutil.rmtree(d, ignore_errors=True)


def study_name(case):
    import yaml

    try:
        spec = yaml.safe_load(case["study"])
        return spec["study"] if isinstance(spec, dict) and isinstance(spec.get("study"), str) else None
    except Exception:  # noqa: BLE001 - any study file the runner ran must have loaded here too
        return None


def minimise(run, case, kind_of, problem, budget=30):
    """Greedy: drop folder damage and study-file lines while the case still breaks the same
    oracle; a hang keeps its recipe as it is (every try would cost the whole time bound)."""
    if "did not finish" in problem:
        return case
    kind = kind_of(problem)
    tries = [0]

    def still_fails(c):
        if tries[0] >= budget:
            return False
        tries[0] += 1
        p = run(c)
        return p is not None and kind_of(p) == kind
    case = json.loads(json.dumps(case))
    i = 0
    while i < len(case["folder"]) and len(case["folder"]) > 1:
        trial = dict(case, folder=case["folder"][:i] + case["folder"][i + 1:])
        if still_fails(trial):
            case = trial
        else:
            i += 1
    if case["kind"] == "file" and case["study"]:
        lines = case["study"].split("\n")
        i = 0
        while i < len(lines):
            trial = dict(case, study="\n".join(lines[:i] + lines[i + 1:]))
            if lines[i].strip() and still_fails(trial):
                case, lines = trial, lines[:i] + lines[i + 1:]
            else:
                i += 1
    return case


if __name__ == "__main__":  # a case's recipe: python3 study_files.py SEED K
    print(json.dumps(study_case(random.Random(f"{sys.argv[1]}:{sys.argv[2]}")), indent=1))
