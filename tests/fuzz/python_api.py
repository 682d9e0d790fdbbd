"""The `python` family of the mutation fuzzer (tests/fuzz/fuzz.py --families python): the Python
API of granboltz.lib.inprocess (simulate, Simulation, advance, observe, save, restore) given mutated
configs (dicts with NumPy values, deep nesting, cycles, wrong types, unknown keys), mutated
arguments (threads, ensemble, advance's t, output and save paths: the config itself, hard and
symbolic links, directories, FIFOs, bytes, paths that are not UTF-8, NUL), damaged state files
(h5py edits: zeroed streams, reshaped or cast datasets, deleted or changed attributes; bit flips,
truncations) and one Simulation used from two threads.

Case k of seed s is drawn from random.Random("s:k") alone, as a JSON recipe (values that JSON
cannot hold, such as NumPy scalars and sets, are tagged: see `decode`). Cases run in a worker
process of their own (a crash or a hang there is a finding, not the end of the fuzzer), each in
a fresh directory. The oracle: every call ends in success or in a documented exception, exactly
of one of the types in ALLOWED (a subclass such as RecursionError, UnicodeEncodeError or yaml's
RepresenterError is not one), with a one-line message; a run, a restore or a save that succeeds
is correct (a config of NumPy values is the config of the numbers they hold; a damaged state is
restored only if it equals the sound one; one Simulation used from two threads ends with the
bits of an undisturbed one); no case takes more than TIMEOUT seconds; nothing is left in the
case's directory or the temporary directory but the outputs of calls that succeeded, and the
inputs are unchanged.
"""

import copy
import hashlib
import json
import os
import pathlib
import random
import select
import shutil
import stat
import subprocess
import sys
import tempfile
import time

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parents[1]
BASE = ROOT / "tests" / "bad_inputs" / "base"
TIMEOUT = 20.0  # seconds a case may take (a session starts the worker: a few seconds more)
MAX_MESSAGE = 1200
# Exactly these types (by name): what docs/python.md documents for the API.
ALLOWED = {"ConfigError", "ValueError", "TypeError", "FileNotFoundError", "RunReadError",
           "SimulationBusyError", "RuntimeError"}
RAW = ("incompatible function arguments", "Invoked with", "Traceback", "Unable to ",
       "HDF5-DIAG", "terminate called", "std::", "RepresenterError")
FORBIDDEN_STDERR = ("HDF5-DIAG", "terminate called", "Segmentation fault", "AddressSanitizer",
                    "runtime error:")
C = 0.0795774715459477

# ---------------------------------------------------------------------------------- configs
ENGINES = {
    "plain": {"model": "dsmc", "seed": 3, "ensembles": 2,
              "dsmc": {"particles": 64, "alpha": 0.5, "beta": 1, "gamma": 4,
                       "kernel": {"lambda": 1, "C": C}, "t_end": 0.5, "observe_every": 0.25}},
    "strang": {"model": "dsmc", "seed": 4, "ensembles": 2,
               "dsmc": {"particles": 64, "alpha": 0.5, "beta": 1, "scheme": "strang", "steps": 8,
                        "kernel": {"lambda": 0, "C": C}, "t_end": 0.5, "observe_every": 0.25}},
    "pairwise": {"model": "dsmc", "seed": 5, "ensembles": 2,
                 "dsmc": {"particles": 64, "alpha": 0.5, "beta": 0, "majorant": "pairwise",
                          "kernel": {"lambda": 1, "C": C}, "t_end": 0.5, "observe_every": 0.25}},
    "gaussian": {"model": "dsmc", "seed": 6, "ensembles": 2,
                 "dsmc": {"particles": 64, "alpha": 0.5, "beta": 0, "thermostat": "gaussian",
                          "kernel": {"lambda": 1, "C": C}, "t_end": 0.5, "observe_every": 0.25,
                          "histogram": {"shells": 4, "radius": 5, "component": True}}},
    "swpm": {"model": "dsmc", "seed": 231, "ensembles": 2,
             "dsmc": {"particles": 200, "dimension": 2, "alpha": 0.5, "beta": 1, "gamma": 4,
                      "kernel": {"lambda": 1, "C": 2 * C}, "t_end": 0.5, "observe_every": 0.25,
                      "weights": {"method": "swpm", "kappa": 1, "max_particles": 300,
                                  "reduction": "energy",
                                  "split": {"radius": 3, "rate": 1, "interval": 0.05,
                                            "max_radius": 8}}}},
    "rough": {"model": "dsmc", "seed": 7, "ensembles": 2,
              "dsmc": {"particles": 64, "alpha": 0.5, "beta": 1, "gamma": 4,
                       "kernel": {"lambda": 1, "C": C}, "t_end": 0.5, "observe_every": 0.25,
                       "roughness": {"beta": 0.5, "inertia": 0.4}}},
    "mixture": {"model": "dsmc", "seed": 8, "ensembles": 2,
                "dsmc": {"particles": 64, "alpha": 0.5, "beta": 1, "gamma": 4,
                         "kernel": {"lambda": 1, "C": C}, "t_end": 0.5, "observe_every": 0.25,
                         "species": [{"name": "heavy", "fraction": 0.25, "mass": 3.0, "diameter": 1.0},
                                     {"name": "light", "fraction": 0.75, "mass": 1.0, "diameter": 1.0}]}},
}
STREAMS = ["events_stream", "pairs_stream", "sweep_stream", "reduce_stream", "split_stream",
           "candidates/lane_0", "partners/lane_3"]
# Per engine, a cross-thread case's settings: an advance of about 0.1 to 0.3 s.
THREAD = {"plain": {"t_end": 40.0, "particles": 2000, "gamma": 4},
          "strang": {"t_end": 20.0, "particles": 2000, "gamma": 4, "steps": 4000},
          "pairwise": {"t_end": 5.0, "particles": 100000, "gamma": 4},
          "gaussian": {"t_end": 100.0, "particles": 2000, "gamma": 4},
          "swpm": {"t_end": 20.0},
          "rough": {"t_end": 40.0, "particles": 2000, "gamma": 4},
          "mixture": {"t_end": 30.0, "particles": 2000, "gamma": 4}}


def base_configs():
    import yaml

    out = copy.deepcopy(ENGINES)
    for name in ("intruder", "needle"):
        out[name] = yaml.safe_load((BASE / f"{name}.yaml").read_text())
    return out


# ------------------------------------------------------------------------- tagged values
def decode(v, np=None):
    """A recipe's value as the Python object it stands for: {"$np": dtype, "v": x} a NumPy
    scalar, {"$arr": dtype, "v": list} an array (0-d for a scalar v), {"$tuple"|"$set": list},
    {"$complex": [re, im]}, {"$bytes": hex}, {"$float": "nan"}, {"$object": 1}, {"$deep": n,
    "kind": "list"|"dict"}, {"$keyed": [[key, value], ...]} (a dict with keys of any type),
    {"$npstr": s}, {"$fraction": [p, q]}, {"$decimal": s}, {"$path": "pathlib"|"bytes", "v": s}."""
    if np is None:
        import numpy as np
    if isinstance(v, list):
        return [decode(x, np) for x in v]
    if not isinstance(v, dict):
        return v
    if "$np" in v:
        return np.dtype(v["$np"]).type(v["v"])
    if "$arr" in v:
        return np.array(v["v"], dtype=v["$arr"])
    if "$tuple" in v:
        return tuple(decode(x, np) for x in v["$tuple"])
    if "$set" in v:
        return set(v["$set"])
    if "$complex" in v:
        return complex(*v["$complex"])
    if "$bytes" in v:
        return bytes.fromhex(v["$bytes"])
    if "$float" in v:
        return float(v["$float"])
    if "$object" in v:
        return object()
    if "$npstr" in v:
        return np.str_(v["$npstr"])
    if "$fraction" in v:
        import fractions
        return fractions.Fraction(*v["$fraction"])
    if "$decimal" in v:
        import decimal
        return decimal.Decimal(v["$decimal"])
    if "$zeros" in v:
        return np.zeros(v["$zeros"])
    if "$deep" in v:
        x = [] if v["kind"] == "list" else {}
        for _ in range(v["$deep"]):
            x = [x] if v["kind"] == "list" else {"a": x}
        return x
    if "$keyed" in v:
        return {(tuple(k) if isinstance(k, list) else decode(k, np)): decode(x, np) for k, x in v["$keyed"]}
    if "$path" in v:
        return pathlib.Path(v["v"]) if v["$path"] == "pathlib" else os.fsencode(v["v"])
    return {k: decode(x, np) for k, x in v.items()}


def leaves(tree, prefix=(), seen=None):
    seen = set() if seen is None else seen
    if isinstance(tree, (dict, list)):
        if id(tree) in seen:  # a dict that contains itself (the edit "cycle")
            return
        seen.add(id(tree))
    if isinstance(tree, dict):
        for k, v in tree.items():
            yield from leaves(v, prefix + (k,), seen)
    elif isinstance(tree, list):
        for i, v in enumerate(tree):
            yield from leaves(v, prefix + (i,), seen)
    else:
        yield prefix, tree


def same_value_numpy(rng, value):
    """A NumPy stand-in holding exactly `value` (a bool, int or float of a config)."""
    if isinstance(value, bool):
        return rng.choice([{"$np": "bool_", "v": value}, {"$arr": "bool", "v": value}])
    if isinstance(value, int):
        kinds = ["int64", "uint64", "int32"] + (["uint8", "int16"] if 0 <= value < 128 else [])
        if 0 <= value < 2**31:
            return rng.choice([{"$np": rng.choice(kinds), "v": value}, {"$arr": "int64", "v": value}])
        if -(2**63) <= value < 2**63:
            return {"$np": "int64", "v": value}
        if 0 <= value < 2**64:
            return {"$np": "uint64", "v": value}
        return value  # no NumPy integer holds it: stays a Python int
    if isinstance(value, float):
        kinds = ["float64", "longdouble"] + (["float32", "float16"] if value in (0.0, 0.25, 0.5, 1.0, 2.0, 3.0, 4.0) else [])
        return rng.choice([{"$np": rng.choice(kinds), "v": value}, {"$arr": "float64", "v": value}])
    return value


# Values that are not config values, or are the wrong type, or deep: each must be refused cleanly.
def odd_value(rng):
    choices = [
        {"$set": [1, 2]}, {"$complex": [1, 2]}, {"$bytes": "ff00"}, {"$object": 1}, None,
        {"$float": "nan"}, {"$float": "inf"}, {"$float": "-inf"}, 2**70, -(2**70), 2**64, -1,
        True, False, "1", "0.5", "", "x" * 5000, "\udcff", "a\nb", "\x1b[31m", "\u202e",
        {"$np": "complex128", "v": 1}, {"$arr": "float64", "v": [0.1, 0.2, 0.3]},
        {"$arr": "float64", "v": [[1.0, 2.0], [3.0, 4.0]]}, {"$arr": "int64", "v": []},
        {"$arr": "float64", "v": [0.5]}, {"$arr": "U3", "v": ["abc"]}, {"$np": "datetime64", "v": "2020-01-01"},
        {"$npstr": "gaussian"}, {"$fraction": [1, 2]}, {"$decimal": "0.5"},
        {"$deep": rng.choice([3, 40, 63, 64, 65, 66, 200, 500, 3000]), "kind": rng.choice(["list", "dict"])},
        {"$tuple": [1, 2]}, [], {}, {"x": 1}, [[[]]], {"$keyed": [[1, 2]]}, {"$keyed": [[None, 1]]},
        {"$keyed": [[[1, 2], 3]]}, {"$keyed": [[{"$npstr": "alpha"}, 0.5]]},
        {"$np": "float64", "v": 1e308}, {"$np": "float32", "v": 0.1}, {"$np": "int8", "v": -3},
        {"$np": "uint64", "v": 2**64 - 1}, {"$np": "float64", "v": -0.0}, 5e-324, 1e308,
        10**12, {"$np": "int64", "v": 10**9}, {"$zeros": rng.choice([1000, 200000])},
    ]
    return rng.choice(choices)


def mutate_config(rng, config):
    """Edits of a config dict as JSON-able operations on its tree."""
    edits = []
    for _ in range(rng.choice([0, 1, 1, 1, 2, 3])):
        paths = [p for p, _ in leaves(config)]
        what = rng.random()
        if what < 0.35 and paths:  # the same value as a NumPy scalar or 0-d array: must be equal
            p = rng.choice(paths)
            edits.append({"op": "set", "path": list(p), "value": same_value_numpy(rng, get(config, p)),
                          "equivalent": True})
        elif what < 0.7 and paths:
            edits.append({"op": "set", "path": list(rng.choice(paths)), "value": odd_value(rng)})
        elif what < 0.78 and paths:
            edits.append({"op": "del", "path": list(rng.choice(paths))})
        elif what < 0.86:
            parent = rng.choice([[], ["dsmc"]] + ([list(rng.choice(paths))[:-1]] if paths else []))
            edits.append({"op": "set", "path": parent + [rng.choice(["extra", "Alpha", "alpha ", "é", "x" * 300])],
                          "value": odd_value(rng) if rng.random() < 0.5 else 1})
        elif what < 0.93:
            edits.append({"op": "cycle", "path": rng.choice([["dsmc"], ["dsmc", "kernel"], []])})
        else:
            edits.append({"op": "numpy_all"})
    return edits


def get(tree, path):
    for k in path:
        tree = tree[k]
    return tree


def apply_edits(config, edits, np):
    """The config dict of the recipe's edits (in the worker: NumPy values are objects)."""
    config = copy.deepcopy(config)
    rng = random.Random(json.dumps(edits, sort_keys=True))
    for e in edits:
        try:
            if e["op"] == "numpy_all":
                for p, v in list(leaves(config)):
                    if isinstance(v, (bool, int, float)) and not isinstance(v, np.generic) and p:
                        parent = get(config, p[:-1])
                        parent[p[-1]] = decode(same_value_numpy(rng, v), np)
                continue
            parent = get(config, e["path"][:-1]) if e["path"] else None
            if e["op"] == "cycle":
                target = get(config, e["path"])
                if isinstance(target, dict):
                    target["loop"] = target
                continue
            key = e["path"][-1]
            if e["op"] == "del":
                del parent[key]
            else:
                parent[key] = decode(e["value"], np)
        except (KeyError, IndexError, TypeError):
            pass  # an earlier edit removed or replaced the path
    return config


def equivalent_only(edits):
    return all(e.get("equivalent") or e["op"] == "numpy_all" for e in edits)


# ---------------------------------------------------------------------------------- paths
# How a path argument is given. Each is made in the case's directory by the worker.
OUTPUT_KINDS = ["new", "new", "new", "bytes", "pathlib", "nonutf8", "existing", "config", "config_dot",
                "config_hardlink", "config_symlink", "dangling_symlink", "symlink_to_new", "dir",
                "dir_slash", "fifo", "missing_dir", "empty", "nul", "int", "none_dir_file", "devnull"]


# ---------------------------------------------------------------------------------- cases
def python_case(rng):
    configs = ENGINES_AND_MODELS
    command = rng.choices(["simulate", "simulation", "restore", "threads"], [0.3, 0.25, 0.3, 0.15])[0]
    if command == "threads":
        engine = rng.choice(list(THREAD))
        members = rng.sample(["velocities", "weights", "spins", "counts", "time", "observe", "advance",
                              "save", "repr", "config", "t_end", "run", "restore_other"], rng.randint(3, 8))
        return {"family": "python", "command": "threads", "base": engine, "members": members,
                "note": f"{engine}: {', '.join(members)}"}
    if command == "restore":
        engine = rng.choice(list(ENGINES))
        damage = []
        for _ in range(rng.choice([0, 1, 1, 1, 2, 3])):
            damage.append(state_damage(rng))
        path = rng.choices(["state", "symlink", "dir", "fifo", "missing", "text", "output", "bytes",
                            "nonutf8", "pathlib", "int", "nul", "devnull"],
                           [10, 1, 1, 1, 1, 1, 1, 1, 1, 1, 0.5, 0.5, 0.5])[0]
        t = rng.choice([0.0, 0.25, 0.5])
        return {"family": "python", "command": "restore", "base": engine, "t": t, "damage": damage,
                "path": path, "note": f"{engine} at t = {t}, {path}: {json.dumps(damage)[:120]}"}
    base = rng.choice(list(configs))
    edits = mutate_config(rng, configs[base]) if rng.random() < (0.7 if command == "simulate" else 0.4) else []
    given = rng.choices(["dict", "path", "bytes_path", "pathlib", "text", "int"], [6, 2, 1, 1, 0.3, 0.2])[0]
    case = {"family": "python", "command": command, "base": base, "edits": edits, "given": given}
    if command == "simulate":
        case["output"] = rng.choice(OUTPUT_KINDS + ["none"] * 3)
        case["threads"] = rng.choice([None, None, 0, 1, 2, -1, 1024, 1025, 2**70, True, False,
                                      {"$float": "2.0"}, "1", {"$np": "int64", "v": 1},
                                      {"$np": "uint8", "v": 2}, 1.5, {"$np": "float64", "v": 1.0}])
        case["progress"] = rng.random() < 0.1
        case["note"] = f"{base} as {given}, output {case['output']}, threads {case['threads']!r}: {json.dumps(edits)[:120]}"
    else:
        case["ensemble"] = rng.choice([0, 1, {"$np": "int64", "v": 1}, {"$np": "uint64", "v": 0}] * 4
                                      + [-1, 2, 2**64 - 1, 2**64, True, "0", 1.0, None])
        actions = []
        for _ in range(rng.randint(1, 6)):
            actions.append(action(rng))
        case["actions"] = actions
        case["note"] = f"{base} as {given}, ensemble {case['ensemble']!r}: {json.dumps(actions)[:100]} {json.dumps(edits)[:80]}"
    return case


def action(rng):
    do = rng.choices(["advance", "observe", "get", "save", "restore_saved", "repr", "run"],
                     [5, 2, 2, 2, 1, 1, 1])[0]
    if do == "advance":
        t = rng.choice([0.0, 0.0625, 0.125, 0.25, 0.3, 0.5, 0.75, -1.0, {"$float": "nan"},
                        {"$float": "inf"}, 1e308, 10**400, "1", "0.25", True, None, [0.25],
                        {"$np": "float64", "v": 0.25}, {"$np": "float32", "v": 0.5},
                        {"$np": "int64", "v": 0}, {"$arr": "float64", "v": 0.25},
                        {"$fraction": [1, 4]}, {"$decimal": "0.25"}, {"$complex": [0.25, 0]}])
        return {"do": "advance", "t": t}
    if do == "get":
        return {"do": "get", "name": rng.choice(["velocities", "spins", "weights", "counts", "time",
                                                  "t_end", "ensemble", "dimension", "config"])}
    if do == "save":
        return {"do": "save", "path": rng.choice(OUTPUT_KINDS)}
    return {"do": do}


def state_damage(rng):
    what = rng.choices(["zero_stream", "reshape", "cast", "delete", "value", "attr", "flip", "truncate",
                        "zero_bytes", "extra", "stream_value"], [3, 2, 3, 1, 2, 2, 2, 1, 1, 1, 1])[0]
    if what in ("zero_stream", "stream_value"):
        d = {"kind": what, "stream": rng.choice(STREAMS)}
        if what == "stream_value":
            d["word"] = rng.randrange(5)
            d["value"] = rng.choice([0, 1, 2**64 - 1, 2**63])
        return d
    if what in ("reshape", "cast", "delete", "value"):
        d = {"kind": what, "nth": rng.randrange(64)}
        if what == "cast":
            d["dtype"] = rng.choice(["int32", "float32", "int64", "uint32", "float16", "uint64", "float64", "S8"])
        if what == "value":
            d["value"] = rng.choice(["nan", "inf", "-inf", -1.0, 0.0, 1e308, 5e-324, 2.0**64, 3.5])
            d["index"] = rng.randrange(1000)
        if what == "reshape":
            d["how"] = rng.choice(["flat", "column", "transpose", "3d"])
        return d
    if what == "attr":
        return {"kind": "attr", "name": rng.choice(["kind", "config", "config_hash", "digest", "ensemble"]),
                "value": rng.choice([None, "", "simulation", "checkpoint", 0, 1, 7, 2**64 - 1, -1, 0.5,
                                     "model: dsmc\n", "edit"])}
    if what == "extra":
        return {"kind": "extra", "name": rng.choice(["/state/extra", "/extra", "/state/particles2"])}
    return {"kind": what, "at": rng.random(), "bit": rng.randrange(8), "length": rng.choice([1, 16, 512, 4096])}


ENGINES_AND_MODELS = None  # set on first use (the TV06 configs are read from tests/bad_inputs/base)


def make_case(rng):
    """fuzz.py's FAMILIES entry."""
    global ENGINES_AND_MODELS
    if ENGINES_AND_MODELS is None:
        ENGINES_AND_MODELS = base_configs()
    return python_case(rng)


# ------------------------------------------------------------------------------ the worker
class Worker:
    """The cases' interpreter: one request per line on stdin, answers (one JSON line each) on a
    pipe of their own, so that nothing the library prints can break them; stderr to a file."""

    def __init__(self):
        self.proc = None
        self.err = None
        self.binary = str(ROOT / "build" / "granboltz")

    def start(self):
        self.err = tempfile.TemporaryFile()
        # tmp: the worker's TMPDIR, which must stay empty; scratch: the harness's own files
        self.home = pathlib.Path(tempfile.mkdtemp(prefix="granboltz-fuzz-python-"))
        self.tmp = self.home / "tmp"
        self.tmp.mkdir()
        (self.home / "scratch").mkdir()
        r, w = os.pipe()
        env = dict(os.environ, PYTHONPATH=str(ROOT / "src" / "python"), TMPDIR=str(self.tmp),
                   GRANBOLTZ_FUZZ_FD=str(w), GRANBOLTZ_FUZZ_BIN=self.binary,
                   GRANBOLTZ_FUZZ_SCRATCH=str(self.home / "scratch"))
        self.proc = subprocess.Popen([sys.executable, str(pathlib.Path(__file__).resolve()), "--worker"],
                                     stdin=subprocess.PIPE, stdout=subprocess.DEVNULL, stderr=self.err,
                                     env=env, pass_fds=(w,), text=True)
        os.close(w)
        self.answers, self.pending = r, b""  # read with os.read: select sees no buffered lines

    def stderr_since(self, offset):
        self.err.seek(offset)
        return self.err.read().decode("utf-8", "replace")

    def ask(self, request, timeout):
        if self.proc is None or self.proc.poll() is not None:
            self.start()
        offset = self.err.seek(0, os.SEEK_END)
        self.proc.stdin.write(json.dumps(request) + "\n")
        self.proc.stdin.flush()
        answers = []
        deadline = time.monotonic() + timeout
        while True:
            while b"\n" in self.pending:
                line, self.pending = self.pending.split(b"\n", 1)
                answer = json.loads(line)
                if answer.get("final"):
                    return answers, answer, self.stderr_since(offset)
                answers.append(answer)
            left = deadline - time.monotonic()
            ready, _, _ = select.select([self.answers], [], [], max(0.0, left))
            if not ready:
                err = self.stderr_since(offset)
                self.stop()
                return answers, {"status": "hang"}, err
            chunk = os.read(self.answers, 1 << 16)
            if not chunk:
                rc = self.proc.wait()
                err = self.stderr_since(offset)
                self.stop()
                return answers, {"status": "died", "rc": rc}, err
            self.pending += chunk

    def stop(self):
        if self.proc is not None:
            self.proc.kill()
            self.proc.wait()
            self.proc = None
            os.close(self.answers)
            shutil.rmtree(self.home, ignore_errors=True)

    def tmp_leftovers(self):
        return sorted(os.listdir(self.tmp)) if self.proc is not None else []


_worker = Worker()


def stop():
    _worker.stop()


def snapshot(d):
    """name -> what the entry is (regular files by content, links by target)."""
    out = {}
    for name in os.listdir(d):
        p = os.path.join(d, name)
        st = os.lstat(p)
        if stat.S_ISLNK(st.st_mode):
            out[name] = "link:" + os.fsdecode(os.readlink(p))
        elif stat.S_ISREG(st.st_mode):
            with open(p, "rb") as f:
                out[name] = "file:" + hashlib.sha256(f.read()).hexdigest()
        elif stat.S_ISDIR(st.st_mode):
            out[name] = "dir:" + ",".join(sorted(os.listdir(p)))
        else:
            out[name] = f"mode:{stat.S_IFMT(st.st_mode)}"
    return out


def message_problem(call, exc, msg):
    """What is wrong with an exception, if anything: "<function> <problem>: <call>: <message>"
    (the part before the first colon is the finding's kind, fuzz.kind_of)."""
    op = call.split("(")[0].split(" ")[0]
    shown = f"{call[:60]}: {msg[:150]!r}"
    if exc not in ALLOWED:
        return f"{op} raised {exc}, not a documented exception: {shown}"
    if "\n" in msg or "\r" in msg:
        return f"{op} {exc} message of {msg.count(chr(10)) + 1} lines: {shown}"
    if not msg.strip():
        return f"{op} {exc} without a message: {call[:60]}"
    if len(msg) > MAX_MESSAGE:
        return f"{op} {exc} message of more than {MAX_MESSAGE} characters: {shown}"
    for raw in RAW:
        if raw in msg:
            return f"{op} {exc} message holds {raw!r}: {shown}"
    return None


def run_case(fuzzer, case):
    """fuzz.py's run_case for this family: None if the case passes, else its problem."""
    d = tempfile.mkdtemp(prefix="granboltz-fuzz-py-")
    _worker.binary = getattr(fuzzer, "binary", _worker.binary)
    try:
        answers, final, err = _worker.ask({"case": case, "dir": d}, TIMEOUT)
        if getattr(fuzzer, "verbose", False):
            print(f"    -> {final.get('status')} {[a.get('call', '')[:40] + ' ' + str(a.get('exc')) for a in answers if 'call' in a][:6]}")
        for bad in FORBIDDEN_STDERR:
            if bad in err:
                return f"stderr holds {bad!r}"
        if final["status"] == "hang":
            return f"did not finish within {TIMEOUT:g} s"
        if final["status"] == "died":
            return f"the interpreter died (exit {final['rc']}): {err.strip().splitlines()[-1][:150] if err.strip() else ''}"
        if final["status"] == "harness":
            return f"harness error: {final['error']}"
        before = next((a["snapshot"] for a in answers if "snapshot" in a), None)
        if before is None:
            return "harness error: no snapshot of the inputs"
        made = {name: what for a in answers for name, what in a.get("made", {}).items()}
        for a in answers:
            if "call" in a and a.get("exc"):
                problem = message_problem(a["call"], a["exc"], a["msg"])
                if problem:
                    return problem
            if a.get("problem"):
                return f"{a['call'].split('(')[0]} {a['problem']}: {a['call'][:80]}"
        after = snapshot(d)
        allowed = set(final.get("outputs", []))
        for name, what in before.items():
            if name not in after:
                return f"the input {name!r} was removed"
            if after[name] != what and name not in allowed:
                return f"the input {name!r} was changed"
        for name, what in made.items():  # inputs made after the snapshot (paths of calls)
            if name in allowed:
                continue
            if name not in after:
                return f"the input {name!r} was removed"
            if after[name] != what:
                return f"the input {name!r} was changed"
        new = sorted(set(after) - set(before) - allowed - set(made))
        if new:
            return f"left behind: {new[:5]}"
        left = _worker.tmp_leftovers()
        if left:
            return f"left in the temporary directory: {left[:5]}"
        return None
    finally:
        shutil.rmtree(d, ignore_errors=True)


def minimise(case, still_fails):
    """Greedy: drop config edits, actions, members and damage while the same oracle fails."""
    for key in ("edits", "actions", "members", "damage"):
        i = 0
        while i < len(case.get(key, [])):
            trial = dict(case, **{key: case[key][:i] + case[key][i + 1:]})
            if still_fails(trial):
                case = trial
            else:
                i += 1
    return case


# ----------------------------------------------------------------------- in the worker
LONG = 3.0  # seconds: a valid config the estimate calls longer is not run (as run --max-hours)


def too_long(argument, scratch):
    """Whether `granboltz estimate` calls the run of this config (dict or path) longer than LONG
    seconds on one thread: a valid huge run (C = 1e9) is no fault of the API, only slow. False
    when the config is refused (the call then says why) or the estimate cannot be read."""
    import re

    from granboltz import _core


    from granboltz.lib import arguments as _arguments
    try:
        text, origin, _ = _arguments.config_text(argument)
        normalized = _core.normalized_config(text, origin)
    except BaseException:  # noqa: BLE001 - refused: the call under test says so
        return False
    path = os.path.join(scratch, "estimate.yaml")
    with open(path, "w", encoding="utf-8", errors="surrogateescape") as f:
        f.write(normalized)
    try:
        r = subprocess.run([os.environ["GRANBOLTZ_FUZZ_BIN"], "estimate", path, "--threads", "1"],
                           capture_output=True, text=True, timeout=10)
    except (OSError, subprocess.TimeoutExpired):
        return False
    m = re.search(r"wall time (?:about|more than) ([0-9.e+]+) (s|min|h|days)", r.stdout)
    if not m:
        return False
    return float(m.group(1)) * {"s": 1, "min": 60, "h": 3600, "days": 86400}[m.group(2)] > LONG


def worker_main():
    import numpy as np

    out = os.fdopen(int(os.environ["GRANBOLTZ_FUZZ_FD"]), "w")
    home = os.getcwd()
    global SCRATCH
    SCRATCH = os.environ["GRANBOLTZ_FUZZ_SCRATCH"]

    def send(x):
        out.write(json.dumps(x) + "\n")
        out.flush()

    configs = base_configs()
    for line in sys.stdin:
        req = json.loads(line)
        try:
            os.chdir(req["dir"])
            outputs = execute(req["case"], configs, np, send)
            send({"final": True, "status": "ok", "outputs": outputs})
        except BaseException as e:  # noqa: BLE001 - a failure of the harness itself
            import traceback
            send({"final": True, "status": "harness", "error": f"{type(e).__name__}: {e}"[:300],
                  "trace": traceback.format_exc()[-1500:]})
        finally:
            os.chdir(home)


def make_path(kind, d, config_file, np):
    """The path argument of `kind` (made in d); returns (argument, output name or None)."""
    if kind == "new":
        return "out.h5", "out.h5"
    if kind == "bytes":
        return b"out.h5", "out.h5"
    if kind == "pathlib":
        return pathlib.Path("out.h5"), "out.h5"
    if kind == "nonutf8":
        return b"\xff\xfe-out.h5", os.fsdecode(b"\xff\xfe-out.h5")
    if kind == "existing":
        with open("old.h5", "wb") as f:
            f.write(b"an older file the user names as output\n")
        return "old.h5", "old.h5"
    if kind in ("config", "config_dot", "config_hardlink", "config_symlink"):
        ours = config_file is not None  # else: a file of the same name, which the call may replace
        if not ours:
            with open("c.yaml", "w") as f:
                f.write("model: dsmc\n")
            config_file = "c.yaml"
        if kind == "config":
            return config_file, None if ours else "c.yaml"
        if kind == "config_dot":
            return os.path.join(".", os.fsdecode(config_file)), None if ours else "c.yaml"
        if kind == "config_hardlink":
            os.link(config_file, "hard.yaml")
            return "hard.yaml", None if ours else "hard.yaml"
        os.symlink(config_file, "soft.yaml")
        return "soft.yaml", None
    if kind == "dangling_symlink":
        os.symlink("nowhere.h5", "dangling.h5")
        return "dangling.h5", None
    if kind == "symlink_to_new":
        os.symlink("target.h5", "link.h5")
        return "link.h5", None
    if kind == "dir":
        os.makedirs("adir", exist_ok=True)  # the same argument may come twice in a case
        return "adir", None
    if kind == "dir_slash":
        os.makedirs("bdir", exist_ok=True)
        return "bdir/", None
    if kind == "fifo":
        os.mkfifo("fifo.h5")
        return "fifo.h5", None
    if kind == "missing_dir":
        return "no/such/dir/out.h5", None
    if kind == "empty":
        return "", None
    if kind == "nul":
        return "out\0.h5", None
    if kind == "int":
        return 5, None
    if kind == "none_dir_file":
        with open("plainfile", "w") as f:
            f.write("x")
        return "plainfile/out.h5", None
    if kind == "devnull":
        return "/dev/null", None
    raise ValueError(kind)


def execute(case, configs, np, send):
    """Runs one case in the current (fresh) directory; sends the inputs' snapshot, then one
    answer per call; returns the names of the files that calls which succeeded may write."""
    import granboltz
    from granboltz.lib import arguments as _arguments

    d = os.getcwd()
    outputs = []
    command = case["command"]

    def call(name, fn):
        try:
            value = fn()
            send({"call": name, "exc": None})
            return True, value
        except BaseException as e:  # noqa: BLE001 - judged by the parent
            if isinstance(e, (SystemExit, GeneratorExit)):
                raise
            send({"call": name, "exc": type(e).__name__, "msg": str(e)[:5000]})
            return False, e

    def problem(name, text):
        send({"call": name, "problem": text})

    def path_of(kind):  # make_path, reporting what it made as inputs
        before = set(os.listdir(d))
        arg, name = make_path(kind, d, config_file, np)
        now = snapshot(d)
        send({"made": {n: now[n] for n in set(now) - before}})
        return arg, name

    if command == "threads":
        return run_threads(case, configs, np, send, call, problem)
    if command == "restore":
        return run_restore(case, configs, np, send, call, problem)

    base = configs[case["base"]]
    config = apply_edits(base, case["edits"], np)
    config_file = None
    given = case["given"]
    if given in ("path", "bytes_path", "pathlib", "text"):
        import yaml
        try:
            text = yaml.safe_dump(_arguments._plain(config, "the config", "<fuzz>"), sort_keys=False)
        except BaseException:  # noqa: BLE001 - a dict no YAML file can hold: give the dict
            given = "dict"
        else:
            with open("c.yaml", "w", encoding="utf-8", errors="surrogateescape") as f:
                f.write(text)
            config_file = "c.yaml"
    argument = {"dict": config, "path": "c.yaml", "bytes_path": b"c.yaml", "pathlib": pathlib.Path("c.yaml"),
                "text": "model: dsmc\n", "int": 7}[given]
    send({"snapshot": snapshot(d)})
    if too_long(argument, SCRATCH):
        send({"skipped": "the estimate calls the run longer than the fuzzer waits"})
        return outputs
    equivalent = equivalent_only(case["edits"]) and given == "dict" and case["edits"]

    if command == "simulate":
        kind = case["output"]
        if kind == "none":
            out_arg, out_name = None, None
        else:
            out_arg, out_name = path_of(kind)
        threads = decode(case["threads"], np)
        ok, run = call(f"simulate(output={kind}, threads={threads!r})",
                       lambda: granboltz.simulate(argument, output=out_arg, threads=threads,
                                                  progress=case.get("progress", False)))
        if ok:
            if out_name:
                outputs.append(out_name)
                again = granboltz.read_run(out_name)
                if again.config != run.config:
                    problem("simulate", "the output read back differs from the Run returned")
            if equivalent:
                plain = granboltz.simulate(base, threads=1, progress=False)
                if plain.config != run.config or sorted(plain.observables) != sorted(run.observables) or any(
                        not np.array_equal(plain.observables[k].mean, run.observables[k].mean, equal_nan=True)
                        for k in plain.observables):
                    problem("simulate", "a config of NumPy values gave another run than the plain one")
        return outputs

    ensemble = decode(case["ensemble"], np)
    ok, sim = call(f"Simulation(ensemble={ensemble!r})", lambda: granboltz.Simulation(argument, ensemble=ensemble))
    if not ok:
        return outputs
    if equivalent and sim.config != granboltz.Simulation(base, ensemble=sim.ensemble).config:
        problem("Simulation", "a config of NumPy values gave another config than the plain one")
    saved = None
    for a in case["actions"]:
        do = a["do"]
        if do == "advance":
            t = decode(a["t"], np)
            call(f"advance({t!r})", lambda: sim.advance(t))
        elif do == "observe":
            call("observe()", sim.observe)
        elif do == "get":
            call(a["name"], lambda: getattr(sim, a["name"]))
        elif do == "repr":
            call("repr", lambda: repr(sim))
        elif do == "run":
            call("run()", sim.run)
        elif do == "save":
            arg, name = path_of(a["path"])
            ok, _ = call(f"save({a['path']})", lambda: sim.save(arg))
            if ok and name:
                outputs.append(name)
                saved = name, sim.time, sim.velocities
            elif ok and a["path"] in ("config", "config_dot", "config_hardlink", "config_symlink",
                                      "symlink_to_new", "dangling_symlink", "devnull"):
                problem(f"save({a['path']})", "wrote through a link, over the config or to a device")
        elif do == "restore_saved" and saved:
            ok, back = call("restore(saved)", lambda: granboltz.Simulation.restore(saved[0]))
            if ok and not (back.time == saved[1] and np.array_equal(back.velocities, saved[2])):
                problem("restore(saved)", "the restored state differs from the saved one")
    return outputs


def run_threads(case, configs, np, send, call, problem):
    import threading

    import granboltz

    config = copy.deepcopy(configs[case["base"]])
    config["ensembles"] = 1
    T = THREAD[case["base"]]["t_end"]
    config["dsmc"].update(THREAD[case["base"]], observe_every=T)
    sim, reference = granboltz.Simulation(config), granboltz.Simulation(config)
    send({"snapshot": snapshot(os.getcwd())})
    errors = []

    def advance():
        try:
            sim.advance(T)
        except BaseException as e:  # noqa: BLE001
            errors.append(e)
    calls = {
        "velocities": lambda: sim.velocities, "weights": lambda: sim.weights, "spins": lambda: sim.spins,
        "counts": lambda: sim.counts, "time": lambda: sim.time, "observe": sim.observe,
        "advance": lambda: sim.advance(T), "save": lambda: sim.save("state.h5"), "repr": lambda: repr(sim),
        "config": lambda: sim.config, "t_end": lambda: sim.t_end, "run": sim.run,
        "restore_other": lambda: granboltz.Simulation(config).advance(0.0),
    }
    worker = threading.Thread(target=advance)
    worker.start()
    seen, rounds = {}, 0
    while worker.is_alive():
        rounds += 1
        for name in case["members"]:
            try:
                calls[name]()
                continue
            except BaseException as e:  # noqa: BLE001 - judged by the parent
                exc, msg = type(e).__name__, str(e)
            if (name, exc) not in seen:
                seen[name, exc] = 1
                send({"call": f"{name} during advance", "exc": exc, "msg": msg[:5000]})
    worker.join()
    refusing = {"velocities", "weights", "spins", "counts", "time", "observe", "advance", "save", "run"}
    if not seen and rounds > 1 and refusing & set(case["members"]):
        problem("threads", f"{rounds} rounds of calls during the advance and not one refused")
    if errors:
        send({"call": "advance in the other thread", "exc": type(errors[0]).__name__, "msg": str(errors[0])})
    reference.advance(T)
    if not (sim.time == T and np.array_equal(sim.velocities, reference.velocities) and sim.counts == reference.counts):
        problem("threads", "the state after the advance differs from an undisturbed one")
    return ["state.h5"]


def damage_file(path, damage, np):
    import h5py

    data_edits = [x for x in damage if x["kind"] in ("flip", "truncate", "zero_bytes")]
    h5_edits = [x for x in damage if x not in data_edits]
    if h5_edits:
        with h5py.File(path, "r+") as f:
            names = []
            f.visititems(lambda n, o: names.append(n) if isinstance(o, h5py.Dataset) else None)
            for x in h5_edits:
                k = x["kind"]
                if k in ("zero_stream", "stream_value"):
                    name = "state/" + x["stream"]
                    if name not in f:
                        continue
                    v = f[name][()]
                    if k == "stream_value" and (v.ndim != 1 or x["word"] >= v.size):
                        continue  # an earlier reshape took the stream apart
                    if k == "zero_stream":
                        v[:4] = 0
                    else:
                        v[x["word"]] = np.uint64(x["value"])
                    f[name][...] = v
                elif k in ("reshape", "cast", "delete", "value"):
                    if not names:
                        continue
                    name = x.get("name") or names[x["nth"] % len(names)]  # a recipe may name it
                    if name not in f:
                        continue
                    v = f[name][()]
                    if k == "delete":
                        del f[name]
                        continue
                    if k == "value":
                        if v.ndim == 0 or v.size == 0:
                            continue
                        flat = v.reshape(-1).copy()
                        try:
                            flat[x["index"] % flat.size] = float(x["value"]) if v.dtype.kind == "f" else \
                                (np.uint64(min(max(float(x["value"]), 0), 2**63)) if v.dtype.kind in "u" else 0)
                        except (ValueError, OverflowError):
                            continue
                        f[name][...] = flat.reshape(v.shape)
                        continue
                    if k == "reshape":
                        if v.ndim == 0:
                            continue
                        new = {"flat": v.reshape(-1), "column": v.reshape(-1, 1), "transpose": v.T,
                               "3d": v.reshape((1,) + v.shape)}[x["how"]]
                    else:
                        try:
                            new = v.astype(x["dtype"])
                        except (ValueError, TypeError, OverflowError):
                            continue
                    del f[name]
                    f[name] = new
                elif k == "attr":
                    if x["value"] is None:
                        if x["name"] in f.attrs:
                            del f.attrs[x["name"]]
                    elif x["value"] == "edit" and x["name"] == "config" and "config" in f.attrs:
                        text = f.attrs["config"]
                        text = text.decode() if isinstance(text, bytes) else text
                        f.attrs["config"] = text.replace("alpha: 0.5", "alpha: 0.75")
                    else:
                        f.attrs[x["name"]] = x["value"] if x["value"] != "edit" else "edited"
                elif k == "extra":
                    if x["name"] not in f:
                        f[x["name"]] = np.zeros(3)
    if data_edits:
        data = bytearray(open(path, "rb").read())
        for x in data_edits:
            at = int(x["at"] * len(data))
            if x["kind"] == "flip" and data:
                data[min(at, len(data) - 1)] ^= 1 << x["bit"]
            elif x["kind"] == "truncate":
                del data[at:]
            elif x["kind"] == "zero_bytes":
                data[at:at + x["length"]] = bytes(len(data[at:at + x["length"]]))
        with open(path, "wb") as f:
            f.write(data)


def run_restore(case, configs, np, send, call, problem):
    import granboltz

    config = copy.deepcopy(configs[case["base"]])
    sim = granboltz.Simulation(config, ensemble=1)
    sim.advance(case["t"])
    sim.save("sound.h5")
    shutil.copy("sound.h5", "state.h5")
    damage_file("state.h5", case["damage"], np)
    kind = case["path"]
    if kind == "symlink":
        os.symlink("state.h5", "link.h5")
    argument = {"state": "state.h5", "symlink": "link.h5", "missing": "missing.h5", "bytes": b"state.h5",
                "pathlib": pathlib.Path("state.h5"), "int": 3, "nul": "state\0.h5", "devnull": "/dev/null"}.get(kind)
    if kind == "nonutf8":
        os.rename("state.h5", b"\xff-state.h5")
        argument = b"\xff-state.h5"
    if kind == "dir":
        os.mkdir("adir")
        argument = "adir"
    if kind == "fifo":
        os.mkfifo("fifo.h5")
        argument = "fifo.h5"
    if kind == "text":
        with open("text.h5", "w") as f:
            f.write("model: dsmc\n")
        argument = "text.h5"
    if kind == "output":
        granboltz.simulate(config, output="run.h5", progress=False)
        argument = "run.h5"
    send({"snapshot": snapshot(os.getcwd())})
    ok, back = call(f"restore({kind})", lambda: granboltz.Simulation.restore(argument))
    if ok:
        if kind not in ("state", "symlink", "bytes", "pathlib", "nonutf8"):
            problem(f"restore({kind})", "restored something that is no state")
            return []
        sound = granboltz.Simulation.restore("sound.h5")
        same = (back.time == sound.time and back.config == sound.config
                and np.array_equal(back.velocities, sound.velocities) and back.counts == sound.counts)
        if same:
            t = back.t_end
            ok1, _ = call("advance(t_end) of the restored", lambda: back.advance(t))
            sound.advance(t)
            same = not ok1 or np.array_equal(back.velocities, sound.velocities)
        if not same:
            problem(f"restore({kind})", f"a damaged state was restored with other values: {json.dumps(case['damage'])[:200]}")
    return []


if __name__ == "__main__":
    if sys.argv[1:] == ["--worker"]:
        sys.path.insert(0, str(ROOT / "src" / "python"))
        worker_main()
