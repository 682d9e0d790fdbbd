#!/usr/bin/python3
"""Where the cycles of an event go: instructions, branch mispredictions and cache misses per event.

`perf stat` needs hardware counters, which this virtual machine does not expose (perf reports
"<not supported>"), so the counts come from valgrind's cachegrind, which simulates the caches and
a simple branch predictor: exact instruction counts, approximate misses. Usage (make
bench-counters): counters.py BENCH_BINARY [CONFIG ...]; each config of bench_runs.cpp is run once
under cachegrind and its simulation child is reported.
"""
import csv
import glob
import os
import shutil
import subprocess
import sys
import tempfile

DEFAULT = ["peer_elastic_hs_n1e4", "peer_pairwise_n1e4", "hs_nosplit_n65536",
           "maxwell_nosplit_n4096"]
EVENTS = ["Ir", "Bcm", "Bim", "D1mr", "D1mw", "DLmr", "DLmw"]


def totals(path):
    """The summary line of a cachegrind output file, as {event: count}."""
    names, values = None, None
    with open(path) as f:
        for line in f:
            if line.startswith("events:"):
                names = line.split()[1:]
            elif line.startswith("summary:"):
                values = [int(v) for v in line.split()[1:]]
    return dict(zip(names, values))


def perf_works():
    """True if perf can count cycles here (hardware counters exposed)."""
    try:
        out = subprocess.run(["perf", "stat", "-e", "cycles", "true"], capture_output=True,
                             text=True, timeout=30)
    except (OSError, subprocess.TimeoutExpired):
        return False
    return out.returncode == 0 and "not supported" not in out.stderr


def main():
    if len(sys.argv) < 2:
        sys.exit("usage: counters.py BENCH_BINARY [CONFIG ...]")
    bench, configs = sys.argv[1], sys.argv[2:] or DEFAULT
    if shutil.which("valgrind") is None:
        sys.exit("counters.py: needs valgrind (apt-get install valgrind)")
    print("hardware counters:", "available (use perf stat)" if perf_works() else
          "not exposed on this machine; cachegrind simulation below")
    print(f"{'config':24} {'events':>10} {'instr/event':>12} {'mispredicts/event':>18} "
          f"{'D1 misses/event':>16} {'LL misses/event':>16}")
    for name in configs:
        with tempfile.TemporaryDirectory() as tmp:
            table = os.path.join(tmp, "bench.csv")
            subprocess.run(["valgrind", "--tool=cachegrind", "--cache-sim=yes", "--branch-sim=yes",
                            f"--cachegrind-out-file={tmp}/cg.%p", bench, "--repeat", "1",
                            "--only", name, "--csv", table],
                           check=True, capture_output=True)
            rows = [r for r in csv.DictReader(open(table)) if r["config"] == name]
            if not rows:
                sys.exit(f"counters.py: no benchmark config named {name}")
            events = float(rows[0]["events"])
            # The simulation runs in a child process: the output file with the most instructions.
            t = max((totals(p) for p in glob.glob(f"{tmp}/cg.*")), key=lambda c: c["Ir"])
        per = {k: t.get(k, 0) / events for k in EVENTS}
        print(f"{name:24} {events:10.0f} {per['Ir']:12.0f} {per['Bcm'] + per['Bim']:18.2f} "
              f"{per['D1mr'] + per['D1mw']:16.2f} {per['DLmr'] + per['DLmw']:16.3f}")


if __name__ == "__main__":
    main()
