#!/usr/bin/python3
"""The bit fixture: runs every case of tests/bits/configs with BINARY and compares the digest of
every output dataset (digest.py) with tests/bits/expected/<case>.txt.

Every expected dataset must exist with the same dtype, shape and SHA-256; datasets the output
has and expected/ has not are reported as `new` and allowed (features add datasets).

A config's leading comment lines may hold `# bits: WORD…` directives:
  sweep=KEY:V1,V2,…  one case per value, run with --set KEY=V, named <config>@<last part of
            KEY>=V (e.g. heated_nosplit_global@lambda=0.5); without it the case is the config.
  shards=K  also run the case as K shards (shard 0 on 2 threads) merged by `granboltz merge`:
            the merged file must have the same digests as the plain run.
  resume    also run it on 1 thread with checkpoints every 0.1 s, stop it by SIGTERM once an
            ensemble is complete, check that the checkpoint holds an ensemble in progress, and
            resume it: the same digests again.

Usage: check.py BINARY [--update] [--only NAME…] [--jobs N] [--keep DIR]
  --update  rewrite expected/ from this binary (for a commit that changes bits on purpose and
            says why); the shard and resume variants must still agree with the plain run.
  --only    cases, or configs (all their cases)
Exit status: 0 all identical, 1 a mismatch, a missing dataset or a failed run, 2 bad usage.
"""
import argparse
import concurrent.futures
import glob
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

import h5py

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from digest import digest  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
CONFIGS = os.path.join(HERE, "configs")
EXPECTED = os.path.join(HERE, "expected")
RUN_TIMEOUT = 300  # seconds for one granboltz command: a hang fails instead of blocking


class RunError(Exception):
    pass


def directives(cfg):
    """The `# bits:` words of a config's leading comment lines, as {key: value or True}."""
    out = {}
    with open(cfg) as f:
        for line in f:
            if not line.startswith("#"):
                break
            if line.startswith("# bits:"):
                for word in line[len("# bits:"):].split():
                    key, _, value = word.partition("=")
                    out[key] = value or True
    return out


def cases_of(cfg):
    """[(case name, config path, --set values, directives)] of one config."""
    name = os.path.splitext(os.path.basename(cfg))[0]
    opts = directives(cfg)
    if "sweep" not in opts:
        return [(name, cfg, [], opts)]
    key, _, values = opts["sweep"].partition(":")
    short = key.rsplit(".", 1)[-1]
    return [(f"{name}@{short}={v}", cfg, [f"{key}={v}"], opts) for v in values.split(",")]


def run(binary, args, cwd):
    r = subprocess.run([binary] + args, cwd=cwd, capture_output=True, text=True,
                       timeout=RUN_TIMEOUT)
    if r.returncode != 0:
        raise RunError(f"granboltz {' '.join(args)}: exit {r.returncode}\n{r.stdout}{r.stderr}")
    return r


def plain(binary, cfg, sets, work):
    run(binary, ["run", cfg, "-q", "--threads", "1", *sets, "-o", "plain.h5"], work)
    return os.path.join(work, "plain.h5")


def sharded(binary, cfg, sets, work, count):
    shards = []
    for i in range(count):
        out = f"shard{i}.h5"
        run(binary, ["run", cfg, "-q", "--threads", "2" if i == 0 else "1", *sets,
                     "--set", f"shard.index={i}", "--set", f"shard.count={count}", "-o", out],
            work)
        shards.append(out)
    run(binary, ["merge", *reversed(shards), "-o", "merged.h5"], work)  # any order merges
    return os.path.join(work, "merged.h5")


def checkpoint_contents(checkpoint):
    """(ensembles in progress, ensembles completed) of a checkpoint."""
    with h5py.File(checkpoint, "r") as f:
        running = len(f["in_progress"]) if "in_progress" in f else 0
        done = f["events/ensemble"].shape[0] if "events/ensemble" in f else 0
    return running, done


def interrupted(binary, cfg, sets, work, notes):
    """Runs the case with checkpoints, stops it by SIGTERM once a checkpoint holds a completed
    ensemble (so that the final one holds completed ensembles and one in progress), resumes it.
    When the run finished first, retried, the last time signalling at the first checkpoint."""
    last = ""
    for attempt, need_done in enumerate((1, 1, 0)):
        d = os.path.join(work, f"resume{attempt}")
        os.mkdir(d)
        out, ckpt = os.path.join(d, "resumed.h5"), os.path.join(d, "resumed.h5.checkpoint")
        args = [binary, "run", cfg, "-q", "--threads", "1", *sets,
                "--set", "checkpoint.every_seconds=0.1", "-o", out]
        start = time.monotonic()
        p = subprocess.Popen(args, cwd=d, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                             text=True)
        seen = None
        while p.poll() is None and time.monotonic() - start < RUN_TIMEOUT:
            try:
                stamp = os.stat(ckpt).st_mtime_ns
                if stamp != seen:  # a new checkpoint (each replaces the last by a rename)
                    seen = stamp
                    if checkpoint_contents(ckpt)[1] >= need_done:
                        break
            except OSError:
                pass
            time.sleep(0.01)
        if p.poll() is None:
            p.send_signal(signal.SIGTERM)
        try:
            log, _ = p.communicate(timeout=RUN_TIMEOUT)
        except subprocess.TimeoutExpired:
            p.kill()
            raise RunError("the run did not stop after SIGTERM")
        if p.returncode != 128 + signal.SIGTERM:
            last = (f"exit {p.returncode}, not {128 + signal.SIGTERM}, on SIGTERM (finished "
                    f"first? then lengthen the config) {log}")
            continue
        if not os.path.exists(ckpt) or os.path.exists(out):
            raise RunError("SIGTERM left no checkpoint, or left an output")
        running, done = checkpoint_contents(ckpt)
        if not running:
            last = "the checkpoint holds no ensemble in progress"
            continue
        notes.append(f"SIGTERM after {time.monotonic() - start:.2f} s (attempt {attempt + 1}): "
                     f"{running} ensemble(s) in progress, {done} completed")
        # Without -q, so that the run says it resumes.
        r = run(binary, ["run", cfg, "--threads", "1", *sets, "-o", out], d)
        if "resuming from" not in r.stdout + r.stderr:
            raise RunError("the second run did not resume from the checkpoint: " +
                           r.stdout + r.stderr)
        return out
    raise RunError(f"no mid-run checkpoint in 3 attempts: {last}")


def parse(lines):
    table = {}
    for line in lines:
        path, dtype, shape, sha = line.split()
        table[path] = (dtype, shape, sha)
    return table


def compare(expected, actual):
    """(failures, new): a line for each changed or missing dataset, and the new paths."""
    failures = []
    for path, want in sorted(expected.items()):
        got = actual.get(path)
        if got is None:
            failures.append(f"missing  {path}")
        elif got != want:
            failures.append(f"changed  {path}\n"
                            f"    expected {' '.join(want)}\n"
                            f"    got      {' '.join(got)}")
    return failures, sorted(set(actual) - set(expected))


def check_case(binary, case, update, keep_root):
    """Runs one case in a directory of its own; returns (name, ok, report lines, seconds)."""
    name, cfg, sets, opts = case
    sets = [a for s in sets for a in ("--set", s)]
    t0 = time.monotonic()
    work = tempfile.mkdtemp(prefix=f"{name}-", dir=keep_root)
    report = []
    try:
        variants = {"plain": plain(binary, cfg, sets, work)}
        if "shards" in opts:
            k = int(opts["shards"])
            variants[f"shards={k}+merge"] = sharded(binary, cfg, sets, work, k)
        if "resume" in opts:
            variants["SIGTERM+resume"] = interrupted(binary, cfg, sets, work, report)
        digests = {v: digest(f) for v, f in variants.items()}
        exp_file = os.path.join(EXPECTED, name + ".txt")
        if update:
            base, ok = digests["plain"], True
            for v, lines in digests.items():
                failures, new = compare(parse(base), parse(lines))
                if failures or new:
                    ok = False
                    report.append(f"{v} differs from the plain run: expected/ not written")
                    report += ["  " + s for s in failures] + ["  only here " + p for p in new]
            if ok:
                with open(exp_file, "w") as f:
                    f.write("".join(line + "\n" for line in base))
                report.append(f"wrote expected/{name}.txt ({len(base)} datasets)")
            return name, ok, report, time.monotonic() - t0
        if not os.path.exists(exp_file):
            return name, False, [f"no expected/{name}.txt (check.py --update writes it)"], \
                time.monotonic() - t0
        with open(exp_file) as f:
            expected = parse(line for line in f if line.strip())
        ok = True
        for v, lines in digests.items():
            failures, new = compare(expected, parse(lines))
            ok = ok and not failures
            report += [f"[{v}] {s}" for s in failures] + [f"[{v}] new      {p}" for p in new]
        return name, ok, report, time.monotonic() - t0
    except (RunError, subprocess.TimeoutExpired, OSError) as e:
        return name, False, report + [f"error: {e}"], time.monotonic() - t0
    finally:
        if keep_root is None:
            shutil.rmtree(work, ignore_errors=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("binary")
    ap.add_argument("--update", action="store_true", help="rewrite expected/ from this binary")
    ap.add_argument("--only", nargs="+", metavar="NAME", help="only these cases or configs")
    ap.add_argument("--jobs", type=int, default=2, help="cases run at once (default 2)")
    ap.add_argument("--keep", metavar="DIR", help="keep the outputs under DIR")
    a = ap.parse_args()
    binary = os.path.abspath(a.binary)
    if not os.path.isfile(binary) or not os.access(binary, os.X_OK):
        print(f"check.py: {a.binary}: not an executable", file=sys.stderr)
        return 2
    cases = [c for cfg in sorted(glob.glob(os.path.join(CONFIGS, "*.yaml")))
             for c in cases_of(cfg)]
    stale = sorted(os.path.basename(p) for p in glob.glob(os.path.join(EXPECTED, "*.txt"))
                   if os.path.basename(p)[:-4] not in {c[0] for c in cases})
    if a.only:
        config_of = lambda c: os.path.splitext(os.path.basename(c[1]))[0]  # noqa: E731
        unknown = [n for n in a.only if not any(n in (c[0], config_of(c)) for c in cases)]
        if unknown:
            print(f"check.py: no case or config named {', '.join(unknown)}", file=sys.stderr)
            return 2
        cases = [c for c in cases if c[0] in a.only or config_of(c) in a.only]
        stale = []
    if a.keep:
        os.makedirs(a.keep, exist_ok=True)
    t0 = time.monotonic()
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, a.jobs)) as pool:
        results = list(pool.map(lambda c: check_case(binary, c, a.update, a.keep), cases))
    failed = 0
    for name, ok, report, seconds in results:
        print(f"{'ok  ' if ok else 'FAIL'} {name} ({seconds:.1f} s)")
        for line in report:
            print("     " + line.replace("\n", "\n     "))
        failed += not ok
    for s in stale:
        print(f"FAIL expected/{s}: no case of that name (remove it, or restore its config)")
    print(f"bits: {len(results) - failed} of {len(results)} cases "
          f"{'written' if a.update else 'identical'}, {failed + len(stale)} failed, "
          f"{time.monotonic() - t0:.1f} s")
    return 1 if failed or stale else 0


if __name__ == "__main__":
    sys.exit(main())
