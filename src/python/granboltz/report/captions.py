"""The captions of the Snakemake report (`snakemake --report`): one per item, made from the
description ("what") its rule file registers with report_item(), so that a description is written
once. Rule report writes them to <report_dir>/captions/<rule>.rst; every report() output of a rule
names its rule's caption (an item is what one rule makes: a figure, a table, or both).

Snakemake renders a caption as a Jinja2 template, then as reStructuredText: the description is
escaped for both."""

from .summary import item_parts

# Characters with a meaning in reStructuredText inline markup; a backslash makes them literal.
RST_SPECIAL = "\\*`|_[]<>"
JINJA_OPENERS = ("{{", "{%", "{#")


def rst_text(text):
    """Plain text as reStructuredText that shows it unchanged."""
    return "".join("\\" + c if c in RST_SPECIAL else c for c in text)


def item_caption(group):
    """The caption of one item (the registered parts one rule made): its title and description,
    the description of a further part (e.g. "Fig. 3 data") where it differs, and the rule."""
    first = group[0]
    lines = []
    for i, it in enumerate(group):
        if it["what"] and it["what"] not in (o["what"] for o in group[:i]):
            title = f"{it['paper']} {it['item']}" if i == 0 else it["item"]
            lines.append(f"**{rst_text(title)}** — {rst_text(it['what'].rstrip('.'))}.")
    if not lines:
        lines.append(f"**{rst_text(first['paper'] + ' ' + first['item'])}**.")
    lines.append(f"Made by rule ``{first['rule']}``.")
    text = "\n\n".join(lines) + "\n"
    if any(o in text for o in JINJA_OPENERS):  # shown as written, not as template code
        text = "{% raw %}" + text + "{% endraw %}\n"
    return text


def item_captions(items):
    """{rule: caption} of the registered items (the report's manifest), one per item."""
    captions = {}
    for group in item_parts([(it, None) for it in items]):
        rule = group[0][0]["rule"]
        if rule in captions:
            raise ValueError(f"report items: rule {rule} makes items of two sections "
                             f"({', '.join(sorted({it['paper'] for it in items if it['rule'] == rule}))}); "
                             "its caption can describe one item only")
        captions[rule] = item_caption([it for it, _ in group])
    return captions
