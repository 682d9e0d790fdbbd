"""Rendering a report document (a list of blocks, see granboltz.report) as GitHub Markdown and as
one self-contained HTML page.
"""

import base64
import html
import re

from .numbers import VERDICT_MARKS

# A numeric cell has digits and no words: values, ± intervals, σ distances, percentages, ranges
# ("30-49", "[3.4, 3.9]", "0.99 → 8e-4") and lists; the units σ and s.e. and the exponent e of
# "3.05e-4" are not words. "–", nan and inf (a missing number) count as numeric.
def _is_numeric_cell(text):
    if text in ("–", "nan", "inf"):
        return True
    bare = re.sub(r"(?<=\d)e(?=[+\-−]?\d)", "", text.replace("s.e.", ""))
    return any(c.isdigit() for c in bare) and not any(c.isalpha() and c != "σ" for c in bare)


_MARK_KIND = {mark: kind for kind, mark in VERDICT_MARKS.items()}


def numeric_columns(rows, width):
    """For each of `width` columns: True when every non-empty cell is a number (right-aligned),
    and at least one is; text columns (item, verdict, ...) are left-aligned."""
    out = []
    for i in range(width):
        cells = [str(r[i]).strip() for r in rows if i < len(r) and str(r[i]).strip() not in ("", "–")]
        out.append(bool(cells) and all(_is_numeric_cell(c) for c in cells))
    return out

# ----------------------------------------------------------------------------- rendering
def anchor(text):
    """GitHub-style anchor of a heading."""
    text = re.sub(r"[^\w\- ]", "", text.lower(), flags=re.UNICODE)
    return text.strip().replace(" ", "-")


def _md_cell(text):
    return str(text).replace("|", "\\|").replace("\n", " ")


def render_md(blocks, image_prefix="../"):
    """Markdown (GitHub flavour) of a document; images link to image_prefix + path."""
    out = []
    for block in blocks:
        kind = block[0]
        if kind == "h":
            out.append("#" * block[1] + " " + block[2])
        elif kind == "p":
            out.append(block[1])
        elif kind == "ul":
            out.append("\n".join(f"- {item}" for item in block[1]))
        elif kind == "table":
            header, rows = block[1], block[2]
            rule = "".join("---:|" if n else "---|" for n in numeric_columns(rows, len(header)))
            lines = ["| " + " | ".join(_md_cell(h) for h in header) + " |", "|" + rule]
            lines += ["| " + " | ".join(_md_cell(c) for c in row) + " |" for row in rows]
            out.append("\n".join(lines))
        elif kind == "img":
            out.append(f"![{block[2]}]({image_prefix}{block[1]})")
        elif kind == "code":
            out.append("```\n" + block[1].rstrip("\n") + "\n```")
        else:
            raise ValueError(f"unknown block {kind!r}")
    return "\n\n".join(out) + "\n"


def inline_html(text):
    """Inline Markdown subset to HTML: escape, then `code`, **bold**, [text](#anchor)."""
    text = html.escape(str(text), quote=False)
    text = re.sub(r"`([^`]+)`", r"<code>\1</code>", text)
    text = re.sub(r"\*\*([^*]+)\*\*", r"<strong>\1</strong>", text)
    return re.sub(r"\[([^\]]+)\]\((#[\w\-]+)\)", r'<a href="\2">\1</a>', text)


CSS = """body{font-family:Georgia,serif;max-width:62em;margin:2em auto;padding:0 1em;line-height:1.45;color:#111}
table{border-collapse:collapse;margin:0.8em 0;font-size:0.88em}th,td{border:1px solid #bbb;padding:0.2em 0.5em;text-align:left}
th{background:#eee}th.num,td.num{text-align:right}code,pre{font-family:monospace;font-size:0.9em}
.mark{font-weight:bold;font-family:sans-serif}td.agrees{background:#e8f5e9}.agrees .mark{color:#1b7a2f}
td.differs{background:#fdecea}.differs .mark{color:#c62828}td.questioned{background:#fff4e0}.questioned .mark{color:#b26a00}
td.approximation{background:#eef3fa}.approximation .mark{color:#1f4e8c}
pre{background:#f6f6f6;padding:0.6em;overflow-x:auto}img{max-width:100%}h1,h2,h3{font-family:Helvetica,Arial,sans-serif}"""


def html_cell(text, numeric):
    """One table cell: right-aligned when its column is numeric; a cell that starts with a
    verdict mark (✓ ✗ ⚠ ·) gets the verdict's class, which colours the mark and the cell."""
    text = str(text)
    kind = _MARK_KIND.get(text[:1]) if text[1:2] == " " else None
    if kind:
        return f'<td class="{kind}"><span class="mark">{text[0]}</span>{inline_html(text[1:])}</td>'
    return f'<td class="num">{inline_html(text)}</td>' if numeric else f"<td>{inline_html(text)}</td>"


def render_html(blocks, read_image, title):
    """A self-contained HTML page: inline CSS, images as base64 data URIs (read_image(path) ->
    PNG bytes), no external reference of any kind."""
    body = []
    for block in blocks:
        kind = block[0]
        if kind == "h":
            body.append(f'<h{block[1]} id="{anchor(block[2])}">{inline_html(block[2])}</h{block[1]}>')
        elif kind == "p":
            body.append(f"<p>{inline_html(block[1])}</p>")
        elif kind == "ul":
            body.append("<ul>" + "".join(f"<li>{inline_html(i)}</li>" for i in block[1]) + "</ul>")
        elif kind == "table":
            num = numeric_columns(block[2], len(block[1]))
            head = "".join(('<th class="num">' if n else "<th>") + inline_html(h) + "</th>" for h, n in zip(block[1], num))
            rows = "".join("<tr>" + "".join(html_cell(c, n) for c, n in zip(r, num)) + "</tr>" for r in block[2])
            body.append(f"<table><thead><tr>{head}</tr></thead><tbody>{rows}</tbody></table>")
        elif kind == "img":
            data = base64.b64encode(read_image(block[1])).decode()
            body.append(f'<p><img alt="{html.escape(block[2])}" src="data:image/png;base64,{data}"></p>')
        elif kind == "code":
            body.append(f"<pre>{html.escape(block[1])}</pre>")
        else:
            raise ValueError(f"unknown block {kind!r}")
    return (f'<!DOCTYPE html>\n<html lang="en">\n<head>\n<meta charset="utf-8">\n<title>{html.escape(title)}</title>\n'
            f"<style>\n{CSS}\n</style>\n</head>\n<body>\n" + "\n".join(body) + "\n</body>\n</html>\n")

