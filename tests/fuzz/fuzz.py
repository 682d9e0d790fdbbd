#!/usr/bin/python3
"""Bounded mutation fuzzer of granboltz (tests/fuzz/README.md).

Five families of cases, each built from a seed alone (case k of seed s draws from
random.Random("s:k")), so a seed and a case count replay exactly:
  config  a valid config mutated (keys deleted, duplicated, renamed; extreme values; wrong types;
          YAML damage; anchors and aliases), given to run, validate or estimate;
  set     a valid config with random --set overrides;
  file    an output, shard or checkpoint made at the start of the session, damaged (bit flips,
          truncation, zeroed ranges), given to verify, merge, resume (run beside it) or read_run;
  study   a study file or folder damaged, given to python -m granboltz.study (study_files.py);
  python  granboltz.simulate and Simulation called with odd values, paths, damaged saved states
          and from two threads (python_api.py).
The default is the first three; study and python are asked for by name (--families).
Every case must pass the oracle (check_outcome); a failing case is minimised and written to the
findings directory as a JSON recipe, which --replay runs again. tests/fuzz/corpus/*.json are
replayed first and must all pass.
"""

import argparse
import hashlib
import json
import os
import pathlib
import random
import re
import resource
import select
import shutil
import signal
import subprocess
import sys
import tempfile
import time

import study_files  # the study family (python -m granboltz.study): tests/fuzz/study_files.py
import python_api  # the family `python`: granboltz.simulate and Simulation (tests/fuzz/python_api.py)

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parents[1]
BASE = ROOT / "tests" / "bad_inputs" / "base"
CORPUS = HERE / "corpus"
KNOWN = HERE / "known"
TIMEOUT = 10.0  # seconds a case may take, wall clock
MAX_HOURS = "0.0003"  # about 1 s: a config the estimate calls long is refused, not run
ERROR_PREFIX = "granboltz: error: "
# A message names the key and the value; the value is cut to about 80 characters, paths are not,
# so a line may be long but not unbounded.
MAX_LINE = 600
FORBIDDEN = ("ERROR: AddressSanitizer", "ERROR: LeakSanitizer", "runtime error:", "HDF5-DIAG",
             "terminate called", "Segmentation fault", "Assertion", "core dumped")

# ------------------------------------------------------------------------------------------ configs
# Valid starting points: the three base configs and variants reaching the other code paths.
VARIANTS = {
    "dsmc": ("dsmc", {}),
    "intruder": ("intruder", {}),
    "needle": ("needle", {}),
    "euler": ("dsmc", {"dsmc.scheme": "euler", "dsmc.steps": "4"}),
    "strang": ("dsmc", {"dsmc.scheme": "strang", "dsmc.steps": "2"}),
    "pairwise": ("dsmc", {"dsmc.kernel.lambda": "1", "dsmc.beta": "0", "dsmc.majorant": "pairwise"}),
    "gaussian": ("dsmc", {"dsmc.beta": "0", "dsmc.thermostat": "gaussian"}),
    "swpm": ("dsmc", {"dsmc.weights.method": "swpm", "dsmc.weights.kappa": "1",
                      "dsmc.weights.max_particles": "1000"}),
    "histogram": ("dsmc", {"dsmc.histogram.shells": "8", "dsmc.histogram.radius": "5",
                           "dsmc.steady_from": "0.2", "dsmc.moments": "6"}),
    "shard": ("dsmc", {"shard.index": "1", "shard.count": "2"}),
    "checkpoint": ("dsmc", {"checkpoint.every_seconds": "0.5"}),
    "intruder_dsmc": ("intruder", {"intruder.method": "dsmc", "intruder.bath_particles": "20",
                                   "intruder.histogram.bins": "6", "intruder.histogram.range": "3"}),
    "needle_hist": ("needle", {"needle.velocity_histogram.bins": "6", "needle.velocity_histogram.range": "3",
                               "needle.omega_histogram.bins": "5", "needle.omega_histogram.range": "3",
                               "needle.waiting_time": "inversion", "needle.collisions": "50"}),
}

# Key names the mutations draw from: the schema's (docs/config.md) and some that are not.
KEYS = ["model", "seed", "ensembles", "threads", "shard", "index", "count", "checkpoint", "every_seconds",
        "dsmc", "particles", "scheme", "steps", "alpha", "beta", "thermostat", "gamma", "kernel", "lambda",
        "C", "initial", "temperature", "heat_flux", "from", "from_hash", "drag", "shear", "t_end", "observe_every", "histogram", "shells", "radius",
        "majorant", "majorant_update", "moments", "steady_from", "weights", "method", "kappa",
        "max_particles", "reduction", "split", "rate", "power", "interval", "max_radius", "intruder",
        "bath", "kind", "a", "mass", "collisions", "density", "sample_every", "bath_particles",
        "bath_refresh", "needle", "length", "waiting_time", "velocity_histogram", "omega_histogram",
        "bins", "range", "Alpha", "alpha ", "sede", "<<", "~", "''", "'seed'", "\"model\"", "? [a]",
        "x" * 300, "é", "日本", "k\u202eey", "1", "true", "null", ".inf", "a.b", "-"]

HUGE = "9" * 400
EXTREMES = ["0", "-0", "0.0", "-0.0", "1e-320", "5e-324", "-5e-324", "2.2250738585072014e-308", "1e308",
            "1.7976931348623157e308", "-1.7976931348623157e308", "1e309", "-1", "1", "2", "0.5", "1e-9",
            "9007199254740992", "9007199254740993", "18446744073709551615", "18446744073709551616",
            "-9223372036854775808", "4294967296", "4294967295", "65535", "1e15", "1e19", "1e20", "2e9",
            "1024", "1025", HUGE, "0." + "0" * 300 + "1", "nan", ".nan", ".NaN", "NaN", ".inf", "-.inf",
            "+.inf", "inf", "0x10", "0o17", "1_000", "+1", ".5", "1.", "1e", "e5", "--1", "1e+5",
            "true", "false", "yes", "no", "on", "null", "~", "", "[]", "{}", "[1, 2]", "[[[]]]",
            "{a: 1}", "{lambda: 0, C: 1}", "!!str 1", "!!float 1", "!!int 1", "!!binary aGVsbG8=",
            "!!null ''", "!custom 1", "!<tag:yaml.org,2002:float> 0.5", "'1'", "\"1\"", "'0.5'",
            "\"nan\"", "&a 1", "*undefined", "dsmc", "gaussian", "swpm", "strang", "pairwise",
            "\"" + "x" * 100000 + "\"", "x" * 5000, "\"line1\\nline2\\nline3\"", "\"tab\\there\"",
            "\"\\x01\\x02\\x1b[31m\"", "\"\\0\"", "\"\\u202e\\u0000\"", "αβγ", "😀", "\"\\uFFFF\"",
            "|\n  multi\n  line", ">\n  folded\n  text", "- 1\n- 2", "? a\n: b"]
EXTREME_WEIGHTED = EXTREMES


def scalar_text(v):
    """The YAML text of a value read by yaml.safe_load from the base configs."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return repr(v)
    return str(v)


def load_tree(text):
    """A config as nested dicts whose leaves are YAML texts (the mutations write raw text)."""
    import yaml

    def conv(node):
        if isinstance(node, dict):
            return {str(k): conv(v) for k, v in node.items()}
        return scalar_text(node)
    return conv(yaml.safe_load(text))


def set_path(tree, path, value):
    parts = path.split(".")
    for p in parts[:-1]:
        tree = tree.setdefault(p, {})
    tree[parts[-1]] = value


def emit(tree, indent=0):
    """Block YAML of a tree; a leaf is written as its raw text (multi-line texts are indented)."""
    out = []
    pad = " " * indent
    for k, v in tree.items():
        if isinstance(v, dict):
            out.append(f"{pad}{k}:" + ("\n" + emit(v, indent + 2) if v else " {}"))
        elif "\n" in v:
            first, *rest = v.split("\n")
            out.append(f"{pad}{k}: {first}" + "".join(f"\n{pad}  {r}" for r in rest))
        else:
            out.append(f"{pad}{k}: {v}")
    return "\n".join(out)


def base_config(name):
    model, settings = VARIANTS[name]
    tree = load_tree((BASE / f"{model}.yaml").read_text())
    for path, value in settings.items():
        set_path(tree, path, value)
    return tree


def leaves(tree, prefix=()):
    """Every (path, is_mapping) of a tree; a path is a tuple of keys (a key may hold a dot)."""
    for k, v in tree.items():
        path = prefix + (k,)
        yield path, isinstance(v, dict)
        if isinstance(v, dict):
            yield from leaves(v, path)


def parent_of(tree, path):
    for p in path[:-1]:
        tree = tree[p]
    return tree, path[-1]


def neighbour(rng, value):
    """A value near a valid one: scaled, negated, nudged, written as float or integer."""
    try:
        x = float(value)
    except ValueError:
        return rng.choice(EXTREMES)
    choices = [x * 2, x / 2, x * 1e6, x * 1e-6, -x, x + 1, x - 1, x * (1 + 1e-16), x * 1e300]
    y = rng.choice(choices)
    return rng.choice([repr(y), str(int(y)) if abs(y) < 1e300 else repr(y), f"{y:e}"])


def extreme(rng, old=None):
    if old is not None and rng.random() < 0.4:
        return neighbour(rng, old)
    return rng.choice(EXTREMES)


def mutate_tree(rng, tree):
    """One structural or value mutation, in place; returns its description."""
    paths = list(leaves(tree))
    path, is_map = rng.choice(paths)
    parent, key = parent_of(tree, path)
    op = rng.choice(["delete", "rename", "value", "value", "value", "type", "add", "empty_section",
                     "move"])
    if op == "delete":
        del parent[key]
    elif op == "rename":
        value = parent.pop(key)
        parent[rng.choice(KEYS)] = value
    elif op == "value" and not is_map:
        parent[key] = extreme(rng, parent[key])
    elif op == "type" or (op == "value" and is_map):
        parent[key] = rng.choice(["[1, 2]", "{}", "true", "~", "'text'", "!!str 1", "[{a: 1}]",
                                  "{x: {y: {z: 1}}}", "-", "'" + key + "'"])
    elif op == "add":
        target = parent if rng.random() < 0.5 else tree
        target[rng.choice(KEYS)] = extreme(rng)
    elif op == "empty_section":
        parent[key] = {}
    elif op == "move":  # a valid key put in another section
        value = parent.pop(key)
        sections = [p for p, m in leaves(tree) if m]
        dest = rng.choice(sections + [()])
        (parent_of(tree, dest + ("x",))[0] if dest else tree)[key] = value
    return f"{op} {'.'.join(path)}"


def mutate_text(rng, text):
    """YAML damage on the text: bytes, lines, indentation, anchors, duplicates, truncation."""
    lines = text.split("\n")
    op = rng.choice(["flip", "truncate", "indent", "dup_line", "swap_lines", "anchor", "merge_key",
                     "insert_bytes", "tabs", "alias_bomb", "document", "bom"])
    if op == "flip" and text:
        b = bytearray(text.encode("utf-8", "surrogateescape"))
        for _ in range(rng.randint(1, 4)):
            i = rng.randrange(len(b))
            b[i] ^= 1 << rng.randrange(8)
        return b.decode("utf-8", "surrogateescape"), op
    if op == "truncate" and text:
        return text[:rng.randrange(len(text))], op
    if op == "indent":
        i = rng.randrange(len(lines))
        lines[i] = " " * rng.choice([1, 3, 5]) + lines[i] if rng.random() < 0.5 else lines[i].lstrip()
    elif op == "dup_line":
        i = rng.randrange(len(lines))
        lines.insert(rng.randrange(len(lines) + 1), lines[i])
    elif op == "swap_lines" and len(lines) > 1:
        i, j = rng.randrange(len(lines)), rng.randrange(len(lines))
        lines[i], lines[j] = lines[j], lines[i]
    elif op == "anchor":  # an anchored value reused by an alias elsewhere
        cands = [i for i, l in enumerate(lines) if re.match(r"^\s*\w+: \S", l)]
        if len(cands) >= 2:
            i, j = rng.sample(cands, 2)
            k, _, v = lines[i].partition(": ")
            lines[i] = f"{k}: &A {v}"
            k2, _, _ = lines[j].partition(": ")
            lines[j] = f"{k2}: *A"
    elif op == "merge_key":
        cands = [i for i, l in enumerate(lines) if l.endswith(":") and not l.startswith(" ")]
        if cands:
            i = rng.choice(cands)
            lines[i] += " &S"
            lines.append("extra: {<<: *S}" if rng.random() < 0.5 else "<<: *S")
    elif op == "insert_bytes":
        i = 0 if rng.random() < 0.2 else rng.randrange(len(text) + 1)
        junk = rng.choice([",", "? ", "\x00", "\x01", "\x7f", "\xff", "\t", "\r", "\r\n", "\u2028", "\ufeff", ":", "- ",
                           "{", "}", "[", "]", "&", "*", "!", "|", ">", "%YAML 1.2\n", "#", "'", "\"", "\\",
                           "\udcff"])  # the last: a byte 0xff that is no UTF-8
        return text[:i] + junk + text[i:], op
    elif op == "tabs":
        i = rng.randrange(len(lines))
        lines[i] = "\t" + lines[i]
    elif op == "alias_bomb":  # nested aliases: a few levels only, the reader must refuse or cope
        depth, width = rng.randint(3, 9), rng.randint(2, 9)
        bomb = ["a0: &a0 [x, x]"]
        for d in range(1, depth):
            bomb.append(f"a{d}: &a{d} [" + ", ".join([f"*a{d - 1}"] * width) + "]")
        key = rng.choice(["seed", "dsmc", "extra", "intruder", "needle"])
        return "\n".join(bomb) + f"\n{key}: *a{depth - 1}\n" + text, op
    elif op == "document":
        lines.insert(rng.randrange(len(lines) + 1), rng.choice(["---", "...", "--- !!map", "%TAG ! tag:x,2000:"]))
    elif op == "bom":
        return "\ufeff" + text, op
    return "\n".join(lines), op


def config_case(rng):
    name = rng.choice(sorted(VARIANTS))
    tree = base_config(name)
    notes = [name]
    for _ in range(rng.choice([1, 1, 1, 1, 1, 2, 2, 3, 5])):
        if not tree:
            break
        notes.append(mutate_tree(rng, tree))
    text = emit(tree) + "\n"
    if rng.random() < 0.3:
        text, op = mutate_text(rng, text)
        notes.append(op)
    command = rng.choice(["run", "run", "validate", "estimate"])
    return {"family": "config", "command": command, "config": text, "args": [], "note": "; ".join(notes)}


def set_case(rng):
    name = rng.choice(sorted(VARIANTS))
    tree = base_config(name)
    valid_paths = [".".join(p) for p, _ in leaves(tree)]
    args = []
    for _ in range(rng.choice([1, 1, 1, 2, 2, 3, 4])):
        r = rng.random()
        if r < 0.5:
            key = rng.choice(valid_paths)
        elif r < 0.8:
            key = ".".join(rng.choice(KEYS) for _ in range(rng.randint(1, 3)))
        else:
            key = rng.choice(["", ".", "..", "a.", ".a", "dsmc..alpha", "seed.value", "dsmc.kernel.lambda.x",
                              "a" * 1000, "é.ü", "dsmc.alpha=1", " seed", "seed "])
        value = extreme(rng)
        args.append(rng.choice(["--set", "--set", "--set="]))
        if args[-1] == "--set=":
            args[-1] = f"--set={key}={value}"
        else:
            args.append(f"{key}={value}" if rng.random() < 0.95 else key)
    if rng.random() < 0.1:
        args += rng.choice([["--threads", rng.choice(["0", "2", "1024", "-1", "1e3", "x"])],
                            ["--max-hours", rng.choice(["0", "-1", "nan", "inf", "1e-300", "1e308"])]])
    command = rng.choice(["run", "run", "validate", "estimate"])
    return {"family": "set", "command": command, "config": emit(tree) + "\n", "args": args, "note": name}


# ------------------------------------------------------------------------------------------ files
FILE_ACTIONS = {"dsmc": ["verify", "read_run"], "intruder": ["verify", "read_run"],
                "needle": ["verify", "read_run"], "shard0": ["merge", "verify", "read_run"],
                "checkpoint": ["resume", "verify", "read_run"]}


def file_case(rng, sources):
    source = rng.choice(sorted(FILE_ACTIONS))
    action = rng.choice(FILE_ACTIONS[source])
    size = sources.size(source)
    mutations = []
    for _ in range(rng.choice([1, 1, 2, 3])):
        op = rng.choice(["flip", "flip", "flip", "zero", "truncate", "fill"])
        # Bias towards the superblock and the first object headers, where HDF5 keeps its structure.
        off = rng.randrange(min(size, 4096)) if rng.random() < 0.4 else rng.randrange(size)
        anchor = {}
        if op != "truncate" and rng.random() < 0.35:
            # Inside an HDF5 structure found by its signature: the same place in every session's
            # file, though the files' sizes and layouts vary a little.
            sig, nth = rng.choice(sources.signatures(source))
            anchor = {"anchor": sig, "nth": nth}
            off = rng.randrange(256)
        if op == "flip":
            mutations.append({"op": "flip", "offset": off, "bit": rng.randrange(8), **anchor})
        elif op == "zero":
            mutations.append({"op": "zero", "offset": off, "length": rng.choice([1, 8, 64, 512, 4096]), **anchor})
        elif op == "fill":
            mutations.append({"op": "fill", "offset": off, "length": rng.choice([4, 16, 256]),
                              "byte": rng.choice([0xFF, 0x7F, 0x80]), **anchor})
        else:
            mutations.append({"op": "truncate", "size": rng.randrange(size)})
    return {"family": "file", "command": action, "source": source, "mutations": mutations, "note": ""}


def fletcher_blind(original, damaged):
    """True when the damage only turns 0x00 bytes into 0xFF or back: HDF5's Fletcher-32 sums
    16-bit words modulo 65535, where 0x0000 and 0xFFFF are the same, so it cannot see this."""
    if len(original) != len(damaged) or original == damaged:
        return False
    return all({a, b} == {0, 255} for a, b in zip(original, damaged) if a != b)


def apply_mutations(data, mutations):
    b = bytearray(data)
    for m in mutations:
        if m["op"] == "truncate":
            del b[m["size"]:]
            continue
        off = m["offset"]
        if "anchor" in m:  # relative to the nth occurrence of a byte string (an HDF5 signature)
            starts = [x.start() for x in re.finditer(re.escape(m["anchor"].encode("latin-1")), b)]
            if len(starts) <= m.get("nth", 0):
                continue
            off += starts[m.get("nth", 0)]
        if off >= len(b):
            continue
        if m["op"] == "flip":
            b[off] ^= 1 << m["bit"]
        else:
            end = min(len(b), off + m["length"])
            b[off:end] = bytes([m.get("byte", 0)]) * (end - off)
    return bytes(b)


# ------------------------------------------------------------------------------------------ running
def limits(sanitized):
    def apply():
        os.setsid()
        if not sanitized:  # AddressSanitizer reserves terabytes of address space
            resource.setrlimit(resource.RLIMIT_AS, (4 << 30, 4 << 30))
        resource.setrlimit(resource.RLIMIT_FSIZE, (200 << 20, 200 << 20))
        resource.setrlimit(resource.RLIMIT_CPU, (int(TIMEOUT) + 5, int(TIMEOUT) + 10))
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
    return apply


def run_process(argv, cwd, sanitized, timeout=TIMEOUT):
    start = time.monotonic()
    env = None
    if sanitized:  # LeakSanitizer's table of used suppressions is no message of the program
        env = dict(os.environ)
        env["LSAN_OPTIONS"] = ":".join(filter(None, [env.get("LSAN_OPTIONS"), "print_suppressions=0"]))
    p = subprocess.Popen(argv, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env,
                         stdin=subprocess.DEVNULL, preexec_fn=limits(sanitized))
    try:
        out, err = p.communicate(timeout=timeout)
        timed_out = False
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        out, err = p.communicate()
        timed_out = True
    return {"rc": p.returncode, "stdout": out.decode("utf-8", "replace"), "stderr": err.decode("utf-8", "replace"),
            "timed_out": timed_out, "seconds": time.monotonic() - start}


def snapshot_dir(d):
    return {p.name: hashlib.sha256(p.read_bytes()).hexdigest() if p.is_file() else "dir"
            for p in pathlib.Path(d).iterdir()}


class ReadRunWorker:
    """granboltz.read_run in a child process of its own: a hang or crash of h5py is a finding,
    not the end of the fuzzer. One request per line; the answer is one JSON line."""

    def __init__(self):
        self.proc = None

    def start(self):
        env = dict(os.environ, PYTHONPATH=str(ROOT / "src" / "python"))
        self.proc = subprocess.Popen([sys.executable, str(pathlib.Path(__file__).resolve()), "--read-run-worker"],
                                     stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                     env=env, text=True, preexec_fn=limits(False))

    def ask(self, request, timeout=TIMEOUT):
        if self.proc is None or self.proc.poll() is not None:
            self.start()
        self.proc.stdin.write(json.dumps(request) + "\n")
        self.proc.stdin.flush()
        ready, _, _ = select.select([self.proc.stdout], [], [], timeout)
        if not ready:
            self.stop()
            return {"status": "hang"}
        line = self.proc.stdout.readline()
        if not line:
            rc = self.proc.wait()
            err = self.proc.stderr.read()[-500:]
            self.proc = None
            return {"status": "died", "rc": rc, "stderr": err}
        return json.loads(line)

    def stop(self):
        if self.proc is not None:
            self.proc.kill()
            self.proc.wait()
            self.proc = None


def worker_main():
    """--read-run-worker: {"op": "read", "path": P} reads P with read_run and touches every part
    (histograms too, they are read lazily); "digest" hashes every dataset and the config (the
    provenance, which names times and hosts, left out)."""
    import h5py
    import numpy as np
    from granboltz.output.io import RunReadError
    from granboltz.output.run import read_run

    def feed(h, value):
        if isinstance(value, dict):
            for k in sorted(value, key=str):
                h.update(str(k).encode())
                feed(h, value[k])
        elif isinstance(value, (list, tuple)):
            for v in value:
                feed(h, v)
        elif isinstance(value, np.ndarray) or isinstance(value, np.generic):
            h.update(str(value.dtype).encode() + np.ascontiguousarray(value).tobytes())
        else:
            h.update(repr(value).encode())

    def values_digest(run):
        h = hashlib.sha256()
        feed(h, run.config)
        feed(h, run.time)
        for name in sorted(run.observables):
            o = run.observables[name]
            feed(h, [name, o.mean, o.ci, o.variance, o.per_ensemble])
        for name in sorted(run.histograms):
            feed(h, [name, dict(run.histograms[name])])
        feed(h, [run.events, run.steady, run.exact, run.ensembles, run.model])
        return h.hexdigest()

    def file_digest(path):
        h = hashlib.sha256()
        with h5py.File(path, "r") as f:
            h.update(str(f.attrs.get("config")).encode())
            names = []
            f.visititems(lambda n, o: names.append(n) if isinstance(o, h5py.Dataset) else None)
            for n in sorted(names):
                if n.startswith("provenance"):
                    continue
                h.update(n.encode() + np.ascontiguousarray(f[n][()]).tobytes())
        return h.hexdigest()

    for line in sys.stdin:
        req = json.loads(line)
        try:
            if req["op"] == "digest":
                answer = {"status": "ok", "digest": file_digest(req["path"])}
            else:
                run = read_run(req["path"])
                answer = {"status": "ok", "digest": values_digest(run)}
        except RunReadError as e:
            answer = {"status": "RunReadError", "message": str(e)[:300]}
        except BaseException as e:  # the finding: anything but RunReadError
            answer = {"status": "other", "type": type(e).__name__, "message": str(e)[:300]}
        print(json.dumps(answer), flush=True)


class Sources:
    """The files the file mutants start from, made once per session: outputs of the three models
    (every optional dataset), two shards of one run and their merge, and a checkpoint (a run
    stopped by SIGTERM after its first checkpoint) with its config and the uninterrupted output."""

    SETTINGS = {
        "dsmc": ("dsmc", ["--set", "dsmc.histogram.shells=8", "--set", "dsmc.histogram.radius=5",
                          "--set", "dsmc.steady_from=0.2"]),
        "intruder": ("intruder", ["--set", "intruder.histogram.bins=6", "--set", "intruder.histogram.range=3"]),
        "needle": ("needle", ["--set", "needle.alpha=1", "--set", "needle.velocity_histogram.bins=6",
                              "--set", "needle.velocity_histogram.range=3", "--set", "needle.omega_histogram.bins=5",
                              "--set", "needle.omega_histogram.range=3"]),
        "shard0": ("dsmc", ["--set", "shard.index=0", "--set", "shard.count=2"]),
        "shard1": ("dsmc", ["--set", "shard.index=1", "--set", "shard.count=2"]),
    }
    CHECKPOINT_CONFIG = ("model: dsmc\nseed: 5\nensembles: 2000\ncheckpoint: {every_seconds: 0.01}\n"
                         "dsmc:\n  particles: 1000\n  alpha: 0.5\n  beta: 1\n"
                         "  kernel: {lambda: 0, C: 0.0795774715459477}\n  t_end: 0.5\n  observe_every: 0.25\n")

    def __init__(self, fuzzer):
        self.f = fuzzer
        self.dir = pathlib.Path(tempfile.mkdtemp(prefix="granboltz-fuzz-sources-"))
        self.paths, self.digests, self._signatures = {}, {}, {}

    def _run(self, args):
        r = run_process([self.f.binary, *map(str, args)], self.dir, self.f.sanitized, timeout=120)
        if r["rc"] != 0:
            raise SystemExit(f"fuzz: making the source files failed: {args}: {r['stderr'][-500:]}")

    def make(self):
        for name, (model, extra) in self.SETTINGS.items():
            self.paths[name] = self.dir / f"{name}.h5"
            self._run(["run", BASE / f"{model}.yaml", "-q", "--threads", "1", "-o", self.paths[name], *extra])
        self.paths["merged"] = self.dir / "merged.h5"
        self._run(["merge", self.paths["shard0"], self.paths["shard1"], "-o", self.paths["merged"]])
        cfg = self.dir / "checkpoint.yaml"
        cfg.write_text(self.CHECKPOINT_CONFIG)
        self.paths["checkpoint_config"] = cfg
        self.paths["reference"] = self.dir / "reference.h5"
        self._run(["run", cfg, "-q", "--threads", "1", "-o", self.paths["reference"]])
        self.paths["checkpoint"] = self.make_checkpoint(cfg)
        for name in ("dsmc", "intruder", "needle", "shard0"):
            self.digests[name] = self.f.read_run_digest(self.paths[name], "read")
        self.digests["merged"] = self.f.read_run_digest(self.paths["merged"], "digest")
        self.digests["reference"] = self.f.read_run_digest(self.paths["reference"], "digest")
        # The oracle of a resume is the uninterrupted output: check it holds for the sound checkpoint.
        outcome = self.f.run_file_case({"family": "file", "command": "resume", "source": "checkpoint",
                                        "mutations": []})
        if outcome:
            raise SystemExit(f"fuzz: resuming the sound checkpoint fails the oracle: {outcome}")

    def make_checkpoint(self, cfg):
        out = self.dir / "stopped.h5"
        ckpt = self.dir / "stopped.h5.checkpoint"
        for _attempt in range(5):
            p = subprocess.Popen([self.f.binary, "run", str(cfg), "-q", "--threads", "1", "-o", str(out)],
                                 cwd=self.dir, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            deadline = time.monotonic() + 30
            while not ckpt.exists() and p.poll() is None and time.monotonic() < deadline:
                time.sleep(0.002)
            # A SIGTERM that arrives while a checkpoint is written is lost: send it until the run stops.
            while p.poll() is None and time.monotonic() < deadline:
                p.send_signal(signal.SIGTERM)
                try:
                    p.wait(timeout=0.2)
                except subprocess.TimeoutExpired:
                    pass
            if p.poll() is None:
                p.kill()
                p.wait()
            if ckpt.exists() and not out.exists():
                final = self.dir / "checkpoint.h5.checkpoint"
                ckpt.rename(final)
                return final
            out.unlink(missing_ok=True)
        raise SystemExit("fuzz: could not stop a run after its first checkpoint")

    HDF5_SIGNATURES = ("OHDR", "OCHK", "FRHP", "FHDB", "FHIB", "BTHD", "BTLF", "BTIN", "TREE", "HEAP",
                       "SNOD", "GCOL", "\x89HDF")

    def signatures(self, name):
        """(signature, n) for every HDF5 structure in a source file, in file order."""
        if name not in self._signatures:
            data = self.paths[name].read_bytes()
            found = []
            for sig in self.HDF5_SIGNATURES:
                found += [(sig, n) for n, _ in enumerate(re.finditer(re.escape(sig.encode("latin-1")), data))]
            self._signatures[name] = found or [("\x89HDF", 0)]
        return self._signatures[name]

    def size(self, name):
        return self.paths[name].stat().st_size

    def cleanup(self):
        shutil.rmtree(self.dir, ignore_errors=True)


# ------------------------------------------------------------------------------------------ oracle
def stderr_problem(text, max_lines=3):
    for bad in FORBIDDEN:
        if bad in text:
            return f"stderr holds {bad!r}"
    lines = text.splitlines()
    if not lines:
        return "failed without a message"
    starts = [line.startswith(ERROR_PREFIX) for line in lines]
    if starts[0] and sum(starts) == 1 and len(lines) > 1:
        return f"one message broken over {len(lines)} lines (a value's line breaks printed as they are)"
    if len(lines) > max_lines:
        return f"{len(lines)} lines on stderr (at most {max_lines})"
    for line in lines:
        if not line.startswith(ERROR_PREFIX):
            return f"stderr line not starting with {ERROR_PREFIX!r}: {line[:60]!r}"
        if len(line) > MAX_LINE:
            return f"a message of {len(line)} characters (at most {MAX_LINE}): {line[:100]!r}"
    return None


def process_problem(r, allowed_rc=(0, 1, 2), max_lines=3):
    if r["timed_out"]:
        return f"did not finish within {TIMEOUT:g} s"
    if r["rc"] < 0:
        return f"killed by signal {-r['rc']}"
    if r["rc"] not in allowed_rc:
        return f"exit code {r['rc']}"
    if r["rc"] != 0:
        return stderr_problem(r["stderr"], max_lines)
    for bad in FORBIDDEN:
        if bad in r["stderr"] or bad in r["stdout"]:
            return f"output holds {bad!r}"
    return None


class Fuzzer:
    def __init__(self, binary, sanitized, verbose=False):
        self.binary = os.path.abspath(binary)
        self.sanitized = sanitized
        self.verbose = verbose
        self.worker = ReadRunWorker()
        self.sources = None

    def read_run_digest(self, path, op):
        a = self.worker.ask({"op": op, "path": str(path)})
        if a["status"] != "ok":
            raise SystemExit(f"fuzz: {path}: {op} of a sound file failed: {a}")
        return a["digest"]

    def need_sources(self):
        if self.sources is None:
            self.sources = Sources(self)
            self.sources.make()
        return self.sources

    # A case returns None (passed) or a short description of the oracle it broke.
    def run_case(self, case):
        if case["family"] == "study":
            return study_files.run_case(self, case)
        if case["family"] == "python":
            return python_api.run_case(self, case)
        if case["family"] == "file":
            return self.run_file_case(case)
        return self.run_config_case(case)

    def granboltz(self, args, cwd):
        r = run_process([self.binary, *args], cwd, self.sanitized)
        if self.verbose:
            first = (r["stderr"].strip().splitlines() or [""])[0]
            print(f"    {' '.join(a[:40] for a in args[:2])} ... -> {r['rc']} {r['seconds']:.2f}s {first[:150]}")
        return r

    def run_config_case(self, case):
        d = pathlib.Path(tempfile.mkdtemp(prefix="granboltz-fuzz-"))
        try:
            cfg = d / "case.yaml"
            cfg.write_bytes(case["config"].encode("utf-8", "surrogateescape"))
            before = snapshot_dir(d)
            cmd = case["command"]
            args = [a.replace("{dir}", str(d)) for a in case.get("args", [])]
            argv = [cmd, str(cfg)]
            if cmd == "run":
                argv += ["-q", "--threads", "1", "--max-hours", MAX_HOURS, "-o", str(d / "out.h5")]
            r = self.granboltz(argv + args, d)
            problem = process_problem(r)
            if r["timed_out"]:
                # Whose time was it: the reader's (validate hangs too) or the run's, which the
                # estimate should have refused under --max-hours?
                sets = [a for a in args if not a.startswith("--threads") and not a.startswith("--max-hours")]
                v = r if cmd == "validate" else self.granboltz(["validate", str(cfg)] + sets, d)
                e = r if cmd != "run" or v["timed_out"] else self.granboltz(
                    ["estimate", str(cfg), "--threads", "1"] + sets, d)
                if v["timed_out"]:
                    problem += " (reading the config: validate does not finish either)"
                elif e["timed_out"]:
                    problem += " (validate finishes: the estimate does not)"
                else:
                    problem += ", though the estimate allowed it under --max-hours " + MAX_HOURS
            if problem:
                return problem
            after = snapshot_dir(d)
            allowed = set(before) | ({"out.h5"} if cmd == "run" and r["rc"] == 0 else set())
            extra = set(after) - allowed
            if extra:
                return f"left behind: {sorted(extra)}"
            if any(after.get(k) != v for k, v in before.items()):
                return "an input was changed or removed"
            if cmd == "run" and r["rc"] == 0:
                if "out.h5" not in after:
                    return "exit 0 without the output"
                a = self.worker.ask({"op": "read", "path": str(d / "out.h5")})
                if a["status"] != "ok":
                    return f"read_run of a fresh output: {a['status']} {a.get('message', '')[:100]}"
                v = self.granboltz(["verify", str(d / "out.h5")], d)
                if v["rc"] != 0:
                    return f"verify of a fresh output: exit {v['rc']}: {v['stderr'][:100]}"
            if cmd == "validate" and r["rc"] == 0:
                return self.round_trip(r["stdout"], d)
            return None
        finally:
            shutil.rmtree(d, ignore_errors=True)

    def round_trip(self, printed, d):
        rt = d / "printed.yaml"
        rt.write_text(printed)
        r = self.granboltz(["validate", str(rt)], d)
        if r["rc"] != 0:
            return f"round trip: the printed config is refused: {r['stderr'].strip()[:200]}"
        if r["stdout"] != printed:
            return "round trip: validate of the printed config prints something else"
        return None

    def run_file_case(self, case):
        problem = self._run_file_case(case)
        if problem and "other values" in problem:
            src = self.need_sources()
            original = src.paths[case["source"]].read_bytes()
            if fletcher_blind(original, apply_mutations(original, case["mutations"])):
                problem += " (only 0x00 and 0xFF bytes swapped, which Fletcher-32 cannot see)"
        return problem

    def _run_file_case(self, case):
        src = self.need_sources()
        d = pathlib.Path(tempfile.mkdtemp(prefix="granboltz-fuzz-"))
        try:
            action, source = case["command"], case["source"]
            data = apply_mutations(src.paths[source].read_bytes(), case["mutations"])
            name = "out.h5.checkpoint" if source == "checkpoint" else f"{source}.h5"
            (d / name).write_bytes(data)
            if action == "merge":
                shutil.copy(src.paths["shard1"], d / "shard1.h5")
            if action == "resume":
                shutil.copy(src.paths["checkpoint_config"], d / "run.yaml")
            before = snapshot_dir(d)
            if action == "read_run":
                a = self.worker.ask({"op": "read", "path": str(d / name)})
                if a["status"] in ("hang", "died", "other"):
                    return f"read_run: {a['status']} {a.get('type', '')}: {a.get('message', a.get('stderr', ''))[:150]}"
                if a["status"] == "ok" and source != "checkpoint" and a["digest"] != src.digests[source]:
                    return "read_run: a damaged file read without error but with other values"
                if a["status"] == "ok" and source == "checkpoint":
                    return "read_run: a checkpoint read as an output"
                return self.unchanged(d, before, set())
            if action == "verify":
                r = self.granboltz(["verify", str(d / name)], d)
                problem = process_problem(r, max_lines=6)  # verify names up to 5 datasets, then a count
                if problem:
                    return problem
                if r["rc"] == 0:
                    digest_op = "digest" if source == "checkpoint" else "read"
                    if source == "checkpoint":
                        return None if data == src.paths[source].read_bytes() else self.unchanged(d, before, set())
                    a = self.worker.ask({"op": digest_op, "path": str(d / name)})
                    if a["status"] != "ok":
                        return f"verify said ok, but read_run: {a['status']}: {a.get('message', '')[:150]}"
                    if a["digest"] != src.digests[source]:
                        return "verify said ok, but read_run gives other values"
                return self.unchanged(d, before, set())
            if action == "merge":
                r = self.granboltz(["merge", str(d / name), str(d / "shard1.h5"), "-o", str(d / "merged.h5")], d)
                problem = process_problem(r)
                if problem:
                    return problem
                if r["rc"] == 0:
                    a = self.worker.ask({"op": "digest", "path": str(d / "merged.h5")})
                    if a["status"] != "ok" or a["digest"] != src.digests["merged"]:
                        return "merge of a damaged shard succeeded with other values"
                return self.unchanged(d, before, {"merged.h5"} if r["rc"] == 0 else set())
            if action == "resume":
                r = self.granboltz(["run", str(d / "run.yaml"), "-q", "--threads", "1", "-o", str(d / "out.h5")], d)
                problem = process_problem(r)
                if problem:
                    return problem
                if r["rc"] == 0:
                    if (d / name).exists():
                        return "a successful resume left its checkpoint"
                    a = self.worker.ask({"op": "digest", "path": str(d / "out.h5")})
                    if a["status"] != "ok" or a["digest"] != src.digests["reference"]:
                        return "resumed from a damaged checkpoint, the output differs from the uninterrupted run"
                    before.pop(name)
                    return self.unchanged(d, before, {"out.h5"})
                return self.unchanged(d, before, set())
            raise ValueError(f"unknown file action {action}")
        finally:
            shutil.rmtree(d, ignore_errors=True)

    @staticmethod
    def unchanged(d, before, allowed_new):
        after = snapshot_dir(d)
        extra = set(after) - set(before) - allowed_new
        if extra:
            return f"left behind: {sorted(extra)}"
        if any(after.get(k) != v for k, v in before.items()):
            return "an input was changed or removed"
        return None


# ------------------------------------------------------------------------------------------ minimising
def kind_of(problem):
    """What a finding is, without its details: minimising keeps this fixed."""
    return re.sub(r"\d+", "N", problem.split(":")[0])[:60]


def minimise(fuzzer, case, problem, budget=60):
    """Greedy: drop config lines, --set arguments and mutations, then shorten long values, while
    the case still breaks the same oracle."""
    kind = kind_of(problem)
    tries = [0]
    if "did not finish" in problem:
        budget = min(budget, 6)  # every try of a hang costs the whole time bound

    def still_fails(c):
        if tries[0] >= budget:
            return False
        tries[0] += 1
        p = fuzzer.run_case(c)
        return p is not None and kind_of(p) == kind

    if case["family"] == "study":
        return study_files.minimise(fuzzer.run_case, case, kind_of, problem)
    case = json.loads(json.dumps(case))
    if case["family"] == "python":
        return python_api.minimise(case, still_fails)
    if case["family"] == "file":
        i = 0
        while i < len(case["mutations"]) and len(case["mutations"]) > 1:
            trial = dict(case, mutations=case["mutations"][:i] + case["mutations"][i + 1:])
            if still_fails(trial):
                case = trial
            else:
                i += 1
        return case
    i = 0
    while i < len(case["args"]):
        step = 2 if case["args"][i] == "--set" else 1
        trial = dict(case, args=case["args"][:i] + case["args"][i + step:])
        if still_fails(trial):
            case = trial
        else:
            i += step
    lines = case["config"].split("\n")
    i = 0
    while i < len(lines):
        trial = dict(case, config="\n".join(lines[:i] + lines[i + 1:]))
        if lines[i].strip() and still_fails(trial):
            case, lines = trial, lines[:i] + lines[i + 1:]
        else:
            i += 1
    # Shorten the longest line (a huge value) by halves while it still fails.
    while lines and tries[0] < budget:
        j = max(range(len(lines)), key=lambda k: len(lines[k]))
        if len(lines[j]) < 40:
            break
        shorter = lines[:j] + [lines[j][:len(lines[j]) // 2 + 10]] + lines[j + 1:]
        trial = dict(case, config="\n".join(shorter))
        if still_fails(trial):
            case, lines = trial, shorter
        else:
            break
    return case


# ------------------------------------------------------------------------------------------ main
FAMILIES = {"config": config_case, "set": set_case, "file": None,
            "study": study_files.study_case, "python": python_api.make_case}
# study and python: only when asked for by name (--families)
WEIGHTS = [("config", 0.45), ("set", 0.3), ("file", 0.25), ("study", 0.1), ("python", 0.25)]


def make_case(seed, k, families):
    rng = random.Random(f"{seed}:{k}")
    r, acc = rng.random() * sum(w for f, w in WEIGHTS if f in families), 0.0
    family = families[-1]
    for f, w in WEIGHTS:
        if f in families:
            acc += w
            if r < acc:
                family = f
                break
    return family, rng


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--binary", default=os.environ.get("GRANBOLTZ_BIN", str(ROOT / "build" / "granboltz")))
    ap.add_argument("--seed", type=int, help="default: the time (printed, to replay with --seed)")
    ap.add_argument("--cases", type=int, help="number of cases (default with --minutes: no limit)")
    ap.add_argument("--minutes", type=float, help="time budget (default with --cases: none)")
    ap.add_argument("--families", default="config,set,file")
    ap.add_argument("--findings", default=None, help="directory for the findings' recipes")
    ap.add_argument("--replay", nargs="*", help="run these recipes (JSON) and nothing else")
    ap.add_argument("--no-corpus", action="store_true", help="skip replaying tests/fuzz/corpus")
    ap.add_argument("--strict", action="store_true", help="known findings (tests/fuzz/known) fail the run too")
    ap.add_argument("--sanitized", action="store_true", help="the binary has AddressSanitizer: no RLIMIT_AS")
    ap.add_argument("--show", type=int, nargs="*", help="print the recipes of these case numbers and exit")
    ap.add_argument("-v", "--verbose", action="store_true", help="print every command and its outcome")
    ap.add_argument("--read-run-worker", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.read_run_worker:
        sys.path.insert(0, str(ROOT / "src" / "python"))
        worker_main()
        return 0
    families = args.families.split(",")
    seed = args.seed if args.seed is not None else int(time.time())
    if args.show is not None:
        for k in args.show:
            family, rng = make_case(seed, k, families)
            print(json.dumps(build_case(family, rng, None), indent=1))
        return 0
    if not os.access(args.binary, os.X_OK):
        print(f"fuzz: {args.binary} is not an executable (build first)", file=sys.stderr)
        return 2
    fz = Fuzzer(args.binary, args.sanitized, args.verbose)
    findings_dir = pathlib.Path(args.findings or tempfile.mkdtemp(prefix="granboltz-fuzz-findings-"))
    findings_dir.mkdir(parents=True, exist_ok=True)
    failures = []
    counts = {}
    started = time.monotonic()
    try:
        if args.replay is not None:
            for path in args.replay:
                case = json.loads(pathlib.Path(path).read_text())
                problem = fz.run_case(case)
                print(f"{path}: {'PASS' if problem is None else 'FAIL: ' + problem}")
                failures += [problem] if problem else []
            return 1 if failures else 0
        if not args.no_corpus:
            corpus = sorted(CORPUS.glob("*.json"))
            for path in corpus:
                problem = fz.run_case(json.loads(path.read_text()))
                if problem:
                    print(f"fuzz: corpus {path.name}: FAIL: {problem}")
                    failures.append(problem)
            print(f"fuzz: corpus: {len(corpus)} cases replayed, {len(failures)} failing")
        print(f"fuzz: seed {seed} (replay: tests/fuzz/fuzz.py --seed {seed}"
              + (f" --cases {args.cases}" if args.cases else "") + ")", flush=True)
        if args.cases is None and args.minutes is None:
            args.cases = 100
        known = [(re.compile(r["match"]), path.name) for path in sorted(KNOWN.glob("*.json"))
                 for r in [json.loads(path.read_text())] if "match" in r]
        known_seen = {}
        seen = {}
        k = 0
        while True:
            if args.cases is not None and k >= args.cases:
                break
            if args.minutes is not None and time.monotonic() - started > 60 * args.minutes:
                break
            family, rng = make_case(seed, k, families)
            case = build_case(family, rng, fz)
            counts[family] = counts.get(family, 0) + 1
            if args.verbose:
                print(f"case {k}: {family} {case['command']} {case.get('note', '')[:100]} {case.get('args', '')}"[:300])
            problem = fz.run_case(case)
            match = next((name for rx, name in known
                          if problem and rx.search(f"{family} {case['command']}: {problem}")), None)
            if match and not args.strict:
                known_seen[match] = known_seen.get(match, 0) + 1
                if args.verbose:
                    print(f"    known ({match}): {problem}")
            elif problem:
                signature = (family, case["command"], kind_of(problem))
                seen.setdefault(signature, 0)
                seen[signature] += 1
                if seen[signature] == 1:
                    small = minimise(fz, case, problem)
                    small["problem"] = fz.run_case(small) or problem
                    small["found"] = {"seed": seed, "case": k}
                    path = findings_dir / f"{family}-{case['command']}-{len(seen):03d}.json"
                    path.write_text(json.dumps(small, indent=1) + "\n")
                    if family == "file":
                        save_file_finding(fz, small, path.with_suffix(""))
                    print(f"fuzz: case {k} ({family} {case['command']}): FINDING: {problem}\n"
                          f"      minimised recipe: {path} (replay: tests/fuzz/fuzz.py --replay {path})",
                          flush=True)
                failures.append(problem)
            k += 1
        elapsed = time.monotonic() - started
        per = ", ".join(f"{f} {n}" for f, n in sorted(counts.items()))
        print(f"fuzz: seed {seed}: {k} cases in {elapsed:.0f} s ({per}); {len(failures)} failing, "
              f"{len(seen)} distinct findings" + (f" in {findings_dir}" if seen else "")
              + f"; {sum(known_seen.values())} known (tests/fuzz/known)"
              + f"; replay: tests/fuzz/fuzz.py --seed {seed} --cases {k}")
        for sig, n in sorted(seen.items()):
            print(f"fuzz:   {n:4d} x {sig[0]} {sig[1]}: {sig[2]}")
        for name, n in sorted(known_seen.items()):
            print(f"fuzz:   {n:4d} x known {name}")
        return 1 if failures else 0
    finally:
        fz.worker.stop()
        python_api.stop()
        if fz.sources is not None:
            fz.sources.cleanup()
        if not args.findings and not any(findings_dir.iterdir()):
            findings_dir.rmdir()


def save_file_finding(fz, case, stem):
    """The damaged file itself and a command that replays it: the session's files (a checkpoint
    above all, stopped at a random moment) differ from one session to the next, so a recipe's
    offsets may miss in another session."""
    src = fz.need_sources()
    stem.mkdir(exist_ok=True)
    source = case["source"]
    name = "out.h5.checkpoint" if source == "checkpoint" else f"{source}.h5"
    (stem / name).write_bytes(apply_mutations(src.paths[source].read_bytes(), case["mutations"]))
    shutil.copy(src.paths[source], stem / ("sound-" + name))
    command = {"verify": f"granboltz verify {name}",
               "merge": f"granboltz merge {name} shard1.h5 -o merged.h5",
               "resume": "granboltz run run.yaml -q --threads 1 -o out.h5",
               "read_run": f"python3 -c 'import granboltz; granboltz.read_run(\"{name}\")'"}[case["command"]]
    if case["command"] == "merge":
        shutil.copy(src.paths["shard1"], stem / "shard1.h5")
    if case["command"] == "resume":
        shutil.copy(src.paths["checkpoint_config"], stem / "run.yaml")
    (stem / "replay.sh").write_text(f"# in this directory (the damaged file is {name}; sound-{name} its original)\n"
                                    f"cp {name} {name}.orig 2>/dev/null; {command}\n")
    print(f"      the damaged file and its replay: {stem}/")


def build_case(family, rng, fz):
    if family == "file":
        if fz is None:
            return {"family": "file", "note": "needs the session's files: run it to see the recipe"}
        return file_case(rng, fz.need_sources())
    return FAMILIES[family](rng)


if __name__ == "__main__":
    sys.exit(main())
