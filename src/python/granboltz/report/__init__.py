"""The reproduction report (reproduction.md and the self-contained .html) and the LaTeX tables.

A document is a list of blocks (tuples):
  ("h", level, text)        heading (its anchor is made from the text)
  ("p", text)               paragraph; inline `code`, **bold** and [text](#anchor)
  ("ul", [text, ...])       bullet list
  ("table", header, rows)   table of inline texts
  ("img", path, alt)        an image (a path relative to the repository root)
  ("code", text)            preformatted text

Modules: numbers (formatting, σ-distances, verdicts), render (Markdown, HTML), latex, the
comparisons of each kind of table (convergence, steady, tails, tv06), summary (one summary row
per item) and document (one function per report section, build_document). The names below are
re-exported for convenience.
"""

from .convergence import compare_convergence, compare_rw05_table1, compare_rw05_table2
from .document import COMPARE, build_document, item_blocks, plain_table, wall_times
from .latex import latex_escape, latex_table
from .numbers import (DASH, LAMBDA_P, PUBLISHED_N, VERDICT_MARKS, Verdict, combined_kind, exact_verdict, fl, marked,
                      num, pci, pm, rounding_ci, signed_z, verdict, verdict_kind, z_score)
from .render import anchor, inline_html, numeric_columns, render_html, render_md
from .steady import compare_effort, compare_replicas, compare_steady
from .tails import compare_tails
from .tv06 import compare_tv06_dsmc, compare_tv06_needle, compare_tv06_temperature

__all__ = ["COMPARE", "DASH", "LAMBDA_P", "PUBLISHED_N", "VERDICT_MARKS", "Verdict", "anchor", "build_document",
           "compare_convergence", "compare_effort", "compare_replicas", "compare_rw05_table1", "compare_rw05_table2",
           "combined_kind", "compare_steady", "compare_tails", "compare_tv06_dsmc", "compare_tv06_needle", "compare_tv06_temperature",
           "exact_verdict", "fl", "inline_html", "item_blocks", "latex_escape", "latex_table", "marked", "num", "numeric_columns", "pci",
           "plain_table", "pm", "render_html", "render_md", "rounding_ci", "signed_z", "verdict", "verdict_kind",
           "wall_times", "z_score"]
