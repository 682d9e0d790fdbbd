"""The rows of the report's summary table: one per item.

A rule that makes a figure and its data table registers both as report items (e.g. "Haff's law"
and "Haff's law (table)", TV06 "Fig. 3" and "Fig. 3 data"), each with its own section; the summary
joins the parts a rule made into one row, so an item is counted once. Its mark is the strongest
outcome of its parts (combined_kind: an ✗ anywhere stays ✗), its text is theirs, once when they
say the same."""

from .numbers import Verdict, combined_kind, marked, verdict_kind
from .render import anchor


def item_parts(parts):
    """Group [(registered item, short verdict)] into items: the parts one rule made, in the order
    of their first registration."""
    groups = {}
    for it, short in parts:
        groups.setdefault((it["paper"], it["rule"]), []).append((it, short))
    return list(groups.values())


def item_cell(heading, group):
    """The item column: the first part's name linked to its section, and the kind of every part
    linked to its own ("Haff's law (figure and table)") where a rule made several."""
    first = group[0][0]
    cell = f"[{first['item']}](#{anchor(heading + ' ' + first['item'])})"
    if len(group) == 1:
        return cell
    kinds = [it["kind"] for it, _ in group]
    labels = kinds if len(set(kinds)) == len(kinds) else [it["item"] for it, _ in group]
    links = [labels[0]] + [f"[{label}](#{anchor(heading + ' ' + it['item'])})"
                           for label, (it, _) in zip(labels[1:], group[1:])]
    return f"{cell} ({' and '.join(links)})"


def item_verdict(group):
    """The short verdict of an item: that of its only part, or the parts' texts (each named by its
    kind unless all are the same) with the strongest of their outcomes."""
    shorts = [short for _, short in group]
    if len(shorts) == 1:
        return shorts[0]
    texts = list(dict.fromkeys(str(s) for s in shorts))
    text = texts[0] if len(texts) == 1 else "; ".join(f"{it['kind']}: {s}" for it, s in group)
    return Verdict(combined_kind(verdict_kind(s) for s in shorts), text)


def summary_rows(heading, parts):
    """Summary rows [section, item, marked verdict, rule] of one section's [(item, short)]."""
    return [[heading, item_cell(heading, group), marked(item_verdict(group)), f"`{group[0][0]['rule']}`"]
            for group in item_parts(parts)]
