"""Beyond the papers: the exponential tail of the homogeneous cooling state of hard spheres with
weighted particles (SWPM, importance splitting along the Gaussian thermostat's drift), one run per
alpha.  Per run: b and A of f ~ exp(-A c^b), c = |v - V|/v0, from the steady histogram
(granboltz.reproduction.hcs_tail.hcs_tail_summary), against b = 1 and A = 8 pi gamma C v0/zeta with the cooling
rate zeta measured in the same run (/steady/cooling_rate), and the depth f/f(0) resolved.
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import h5py  # noqa: E402
import yaml  # noqa: E402

from granboltz.output.files import write_csv, write_json  # noqa: E402
from granboltz.reproduction.hcs_tail import HCS_TAIL_COLUMNS, hcs_tail_row_verdict, hcs_tail_summary  # noqa: E402
from granboltz.analysis.local_exponent import shells_from_h5  # noqa: E402

p = snakemake.params
fit = p.fit
rows, details = [], []
for path in snakemake.input.runs:
    with h5py.File(path, "r") as f:
        config = f.attrs["config"]
        config = yaml.safe_load(config.decode() if isinstance(config, bytes) else str(config))
        zeta = float(f["steady/cooling_rate/mean"][()])
        zeta_ci = float(f["steady/cooling_rate/ci"][()])
    alpha = float(config["dsmc"]["alpha"])
    s = hcs_tail_summary(shells_from_h5(path, steady=True), alpha, zeta, p.gamma, p.C, p.temperature0,
                         {"pool_min_count": fit["pool_min_count"], "tail_from": fit["tail_from"]}, fit["max_rel_ci"])
    s["zeta_ci"] = zeta_ci
    ok, text = hcs_tail_row_verdict(s, fit["b_tol"], fit["A_rel"], fit["depth"])
    print(("agrees: " if ok else "differs: ") + text, "| chi =", s["chi_swpm"], "±", s["chi_swpm_ci"],
          "| zeta =", zeta, "±", zeta_ci, file=sys.stderr)
    rows.append(s)
    details.append({**s, "ok": ok, "text": text})
write_csv(rows, HCS_TAIL_COLUMNS, snakemake.output.csv, digits=5)
write_json({"rows": details}, snakemake.output.summary)
