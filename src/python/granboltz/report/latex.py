"""LaTeX (booktabs) versions of the generated CSV tables."""

import re

# ----------------------------------------------------------------------------- LaTeX
LATEX_SPECIAL = {"\\": r"\textbackslash{}", "&": r"\&", "%": r"\%", "$": r"\$", "#": r"\#", "_": r"\_",
                 "{": r"\{", "}": r"\}", "~": r"\textasciitilde{}", "^": r"\textasciicircum{}"}
LATEX_HEADERS = {
    "E_max": r"$E_{\max}$", "E_end": r"$E_{\mathrm{end}}$", "Conf_end": r"$\mathrm{Conf}_{\mathrm{end}}$",
    "V_inf": r"$\|V\|_\infty$", "T_inf": r"$T_\infty$", "E_max_euler": r"$E_{\max}^{\mathrm{Euler}}$",
    "E_max_strang": r"$E_{\max}^{\mathrm{Strang}}$", "lambda": r"$\lambda$", "b_stderr": r"s.e.\ of $b$",
    "n": r"$n$", "N": r"$N$", "K": r"$K$", "b": r"$b$", "dt": r"$\Delta t$", "theory_b": r"$b$ (theory)",
}


def latex_escape(text):
    """Text with the LaTeX special characters escaped (one pass, so escapes are not re-escaped)."""
    return "".join(LATEX_SPECIAL.get(c, c) for c in str(text))


def latex_table(header, rows):
    """A booktabs tabular (a \\toprule/\\midrule/\\bottomrule table of the CSV cells), numbers
    right-aligned, text left-aligned; known column names become math, others are escaped."""

    def numeric(col):
        cells = [r[col] for r in rows if r[col] != ""]
        return bool(cells) and all(re.fullmatch(r"[-+0-9.eE]+|nan|inf", c) for c in cells)

    align = "".join("r" if numeric(i) else "l" for i in range(len(header)))
    lines = [f"\\begin{{tabular}}{{{align}}}", r"\toprule"]
    lines.append(" & ".join(LATEX_HEADERS.get(h, latex_escape(h)) for h in header) + r" \\")
    lines.append(r"\midrule")
    for row in rows:
        lines.append(" & ".join(latex_escape(c) if c != "" else "--" for c in row) + r" \\")
    lines += [r"\bottomrule", r"\end{tabular}"]
    return "\n".join(lines) + "\n"

