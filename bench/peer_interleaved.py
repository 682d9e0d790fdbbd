#!/usr/bin/python3
"""The peer problem, granboltz against SPARTA, interleaved: repetition k runs SPARTA at n = 10^4,
10^5, 10^6 and then granboltz's peer configs once, so that both medians come from the same
minutes of this shared machine (run one after the other, a drift of the machine's speed between
the two halves would enter the ratio). Prints the peer table (median of --repeat) and writes
bench/sparta.csv (SPARTA's medians) and bench/peer.csv (granboltz's rows, as granboltz_bench
writes them, with medians).

Usage (SPARTA=... make bench-peer): peer_interleaved.py SPA_SERIAL GRANBOLTZ_BENCH [--repeat R]
"""
import argparse
import csv
import io
import os
import statistics
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sparta_peer  # noqa: E402

SIZES = (10**4, 10**5, 10**6)
GOAL = 0.20


def granboltz_once(bench):
    """ns per real collision of each peer config, and the majorant `auto` picks at each n."""
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "peer.csv")
        subprocess.run([bench, "--repeat", "1", "--only", "peer_", "--csv", path], check=True,
                       capture_output=True)
        with open(path) as f:
            rows = list(csv.DictReader(f))
    ns = {r["config"]: float(r["ns_per_real_collision"]) for r in rows
          if not r["config"].startswith("peer_auto") and r["ns_per_real_collision"]}
    auto = {float(r["config"][len("peer_auto_n"):]): r["description"].split(";")[0].split()[-1]
            for r in rows if r["config"].startswith("peer_auto")}
    return ns, auto, rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("sparta")
    ap.add_argument("bench")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--sparta-out", default="bench/sparta.csv")
    ap.add_argument("--out", default="bench/peer.csv")
    a = ap.parse_args()
    species = sparta_peer.find(a.sparta, ["data/ar.species", "bench/ar.species"])
    vss = sparta_peer.find(a.sparta, ["data/ar.hs"])
    sparta = {n: [] for n in SIZES}
    ours, auto, template = {}, {}, None
    for k in range(a.repeat):
        for n in SIZES:
            sparta[n].append(sparta_peer.run_once(a.sparta, n, species, vss))
        ns, auto, template = granboltz_once(a.bench)
        for name, value in ns.items():
            ours.setdefault(name, []).append(value)
        print(f"repetition {k + 1}/{a.repeat} done", file=sys.stderr)
    med = {name: statistics.median(v) for name, v in ours.items()}
    spa = {n: statistics.median(v) for n, v in sparta.items()}
    with open(a.sparta_out, "w") as f:
        f.writelines(f"{n},{spa[n]:.2f}\n" for n in SIZES)
    print(f"peer problem, interleaved with SPARTA (median of {a.repeat}; ns per real collision;"
          f" the range is that of the {a.repeat} repetitions' own ratios)")
    print(f"{'n':<8} {'global':>9} {'pairwise':>9} {'auto':<9} {'auto ns':>9} {'SPARTA':>9} "
          f"{'ratio':>6} {'range':>13} goal <= {GOAL:.2f}")
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(["n", "global_ns", "pairwise_ns", "auto", "auto_ns", "sparta_ns", "ratio",
                     "ratio_min", "ratio_max", "repeats_met", "goal_met", "repeats"])
    for n, tag in zip(SIZES, ("1e4", "1e5", "1e6")):
        g, p = med[f"peer_elastic_hs_n{tag}"], med[f"peer_pairwise_n{tag}"]
        choice = auto[float(n)]
        name = f"peer_pairwise_n{tag}" if choice == "pairwise" else f"peer_elastic_hs_n{tag}"
        chosen = med[name]
        ratio = chosen / spa[n]
        # Each repetition ran SPARTA and granboltz within the same minute: their ratio is free of
        # the machine's slower drifts, and its spread shows how far one run can be trusted.
        paired = [ours_k / sparta_k for ours_k, sparta_k in zip(ours[name], sparta[n])]
        met = sum(r <= GOAL for r in paired)
        print(f"{n:<8.0e} {g:9.1f} {p:9.1f} {choice:<9} {chosen:9.1f} {spa[n]:9.0f} {ratio:6.3f} "
              f"{min(paired):6.3f}-{max(paired):.3f} {'met' if ratio <= GOAL else 'not met'}"
              f" ({met} of {len(paired)} repetitions)")
        writer.writerow([n, f"{g:.1f}", f"{p:.1f}", choice, f"{chosen:.1f}", f"{spa[n]:.1f}",
                         f"{ratio:.3f}", f"{min(paired):.3f}", f"{max(paired):.3f}", met,
                         ratio <= GOAL, a.repeat])
    with open(a.out, "w") as f:
        f.write(out.getvalue())
    print(f"CSV: {a.out}, {a.sparta_out}")


if __name__ == "__main__":
    main()
