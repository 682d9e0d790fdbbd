"""The reproduction report of every GRW05, RW05 and TV06 item:
paper/reproduction.md (for a code host) and paper/reproduction.html (self-contained: figures
as base64 data URIs, inline CSS, no external reference), both rendered from one document
(granboltz.report.build_document): published numbers and ours side by side with confidence
intervals, convergence factors and verdicts, every figure with its caption, provenance.
Also the captions of the Snakemake report (snakemake --report), one per item from its registered
description: <report_dir>/captions/<rule>.rst, which the report() outputs of the rule files name.
"""

import sys

sys.stderr = open(snakemake.log[0], "w", buffering=1)

import csv  # noqa: E402
import json  # noqa: E402
import os  # noqa: E402
import shutil  # noqa: E402

from granboltz.output.files import read_csv, write_text  # noqa: E402
from granboltz.output.io import open_run, run_attrs  # noqa: E402
from granboltz.report import build_document, render_html, render_md  # noqa: E402
from granboltz.report.captions import item_captions  # noqa: E402

inp, items = snakemake.input, snakemake.params.manifest
available = set(inp)
for item in items:  # everything an item refers to must be an input of this step
    for path in [item["output"], item["published"], item["summary"], *item["extra"], *item["runs"],
                 *item["benchmarks"]]:
        if path and path not in available:
            raise ValueError(f"report item {item['paper']} {item['item']}: {path} is not an input of rule report")


def seconds(path):
    with open(path, newline="") as f:
        return float(next(csv.DictReader(f, delimiter="\t"))["s"])


def attrs(path):
    with open_run(path) as f:
        return run_attrs(f)


data = {
    "tables": {path: read_csv(path) for path in inp.tables},
    "published": {path: read_csv(path) for path in inp.published},
    "summaries": {path: json.load(open(path)) for path in inp.summaries},
    "bench": {path: seconds(path) for path in inp.benchmarks},
    "runs": {path: attrs(path) for path in inp.runs},
}
doc = build_document(items, data, snakemake.params.config, snakemake.params.machine, snakemake.params.profile)


def read_image(path):
    if path not in available:
        raise ValueError(f"{path} is not an input of rule report")
    with open(path, "rb") as f:
        return f.read()


# The report directory stands alone: copies of the figures (png, pdf) and tables (csv, tex).
for directory, paths in ((snakemake.output.figures, inp.figures),
                         (snakemake.output.tables, [*inp.tables, *inp.tex])):
    os.makedirs(directory, exist_ok=True)
    for path in paths:
        for p in [path] + ([path[:-4] + ".pdf"] if path.endswith(".png") else []):
            if os.path.exists(p):
                shutil.copyfile(p, os.path.join(directory, os.path.basename(p)))
# Rewritten whole, so that a caption of a rule no longer in the workflow does not linger.
captions = snakemake.output.captions
os.makedirs(captions, exist_ok=True)
for rule, text in item_captions(items).items():
    write_text(text, os.path.join(captions, f"{rule}.rst"))
write_text(render_md(doc, image_prefix=""), snakemake.output.md)
write_text(render_html(doc, read_image, "Reproduction of GRW05, RW05 and TV06"), snakemake.output.html)
print(f"{len(items)} items, {len(data['runs'])} runs, {len(doc)} blocks", file=sys.stderr)
