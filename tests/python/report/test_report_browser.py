"""The self-contained HTML report as a reader sees it: rendered in headless Chromium. Without
Selenium or Playwright: a copy of the page gets a script that inspects the rendered DOM on `load`
and writes its findings as JSON into the page, and `chromium --headless --dump-dom` returns that
DOM. A screenshot of the summary is kept in pytest's tmp dir.

Chromium is a Debian package (`chromium`) installed by `scripts/install-deps.sh --with-browser`
(CI does). Where it is absent these tests skip and say so, unless GRANBOLTZ_REQUIRE_BROWSER=1
(set by .ci/run), where its absence is a failure.

The documentation site (`make docs`, build/docs/html/index.html) is opened the same way: its title,
its text and the pages it links to. Where it is not built that test skips, unless
GRANBOLTZ_REQUIRE_BROWSER=1, where the site must exist."""

import json
import os
import pathlib
import re
import shutil
import subprocess

import pytest

from conftest import ROOT

REPORTS = [p for p in (ROOT / "paper" / "reproduction.html", ROOT / "results" / "report" / "reproduction.html")
           if p.is_file()]
MARKER = "granboltz-browser-check"
# Headless flags that work as root in a container, with no network chatter and no GPU.
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--disable-dev-shm-usage", "--hide-scrollbars", "--window-size=1280,1600"]
# Budget of virtual time for the page's load and the checking script (images are data: URIs).
VIRTUAL_TIME_MS = 10000


def find_chromium():
    """Path of a Chromium binary: $CHROMIUM, else chromium / chromium-browser on PATH, else None."""
    env = os.environ.get("CHROMIUM")
    if env:
        return shutil.which(env)
    return shutil.which("chromium") or shutil.which("chromium-browser")


# Runs on `load`: every fact the tests need, computed from the rendered page (computed styles,
# decoded image sizes, layout boxes), serialised as JSON into a <script type=application/json>.
CHECK_JS = r"""
window.addEventListener('load', function () {
  function align(el) {
    var a = getComputedStyle(el).textAlign, rtl = getComputedStyle(el).direction === 'rtl';
    if (a === 'start' || a === '-webkit-left') return rtl ? 'right' : 'left';
    if (a === 'end' || a === '-webkit-right') return rtl ? 'left' : 'right';
    return a;
  }
  function colours(el) {  // every text colour and background inside a cell, the cell included
    var out = [];
    [el].concat(Array.prototype.slice.call(el.querySelectorAll('*'))).forEach(function (e) {
      var s = getComputedStyle(e);
      out.push({color: s.color, background: s.backgroundColor,
                before: getComputedStyle(e, '::before').content});
    });
    return out;
  }
  var body = getComputedStyle(document.body);
  var out = {body_color: body.color, body_background: body.backgroundColor,
             scroll_height: document.documentElement.scrollHeight,
             scroll_width: document.documentElement.scrollWidth};
  out.images = Array.prototype.map.call(document.images, function (img) {
    return {alt: img.alt, src: img.getAttribute('src').slice(0, 40), complete: img.complete,
            natural_width: img.naturalWidth, natural_height: img.naturalHeight,
            width: img.getBoundingClientRect().width};
  });
  out.links = Array.prototype.map.call(document.querySelectorAll('a[href]'), function (a) {
    var href = a.getAttribute('href'), target = null;
    if (href.charAt(0) === '#') {
      var id = decodeURIComponent(href.slice(1));
      target = id === '' || document.getElementById(id) !== null;
    }
    return {href: href, text: a.textContent, target_exists: target};
  });
  var heading = document.getElementById('summary'), table = null;
  for (var e = heading && heading.nextElementSibling; e; e = e.nextElementSibling) {
    if (e.tagName === 'TABLE') { table = e; break; }
    if (/^H[12]$/.test(e.tagName)) break;
  }
  if (table) {
    var r = table.getBoundingClientRect(), s = getComputedStyle(table);
    out.summary = {top: r.top + window.scrollY, left: r.left + window.scrollX, width: r.width,
                   height: r.height, display: s.display, visibility: s.visibility,
                   opacity: s.opacity, rows: table.rows.length};
  }
  out.tables = Array.prototype.map.call(document.querySelectorAll('table'), function (t, i) {
    var h = t.previousElementSibling;
    while (h && !/^H[1-6]$/.test(h.tagName)) h = h.previousElementSibling;
    var head = t.tHead ? Array.prototype.map.call(t.tHead.rows[0].cells, function (c) {
      return c.textContent.trim(); }) : [];
    var rows = [];
    Array.prototype.forEach.call(t.tBodies, function (b) {
      Array.prototype.forEach.call(b.rows, function (row) {
        rows.push(Array.prototype.map.call(row.cells, function (c) {
          return {text: c.textContent.trim(), align: align(c), colours: colours(c)};
        }));
      });
    });
    return {index: i, heading: h ? h.id || h.textContent.trim() : '', is_summary: t === table,
            head: head, rows: rows};
  });
  var node = document.createElement('script');
  node.type = 'application/json';
  node.id = '__MARKER__';
  node.textContent = JSON.stringify(out).replace(/</g, '\\u003c');
  document.body.appendChild(node);
});
""".replace("__MARKER__", MARKER)


def run_chromium(chromium, args, cwd):
    """Run headless Chromium with a fresh profile; returns stdout (raises with stderr on error)."""
    profile = pathlib.Path(cwd) / "profile"
    profile.mkdir(exist_ok=True)
    cmd = [chromium, *FLAGS, f"--user-data-dir={profile}", f"--virtual-time-budget={VIRTUAL_TIME_MS}", *args]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=180, cwd=cwd)
    if proc.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} exited with {proc.returncode}:\n{proc.stderr[-2000:]}")
    return proc.stdout


def render(report, workdir):
    """The findings of CHECK_JS on `report` rendered in Chromium, and a screenshot of its summary."""
    chromium = find_chromium()
    if chromium is None:
        message = ("Chromium not installed: the browser test of the report did not run "
                   "(install it with `bash scripts/install-deps.sh --with-browser`)")
        if os.environ.get("GRANBOLTZ_REQUIRE_BROWSER") == "1":
            pytest.fail(message + "; GRANBOLTZ_REQUIRE_BROWSER=1 requires it")
        pytest.skip(message)
    workdir.mkdir(parents=True, exist_ok=True)
    page = report.read_text(encoding="utf-8")
    assert page.count("</body>") == 1, f"{report}: expected one </body>"
    checked = workdir / "checked.html"
    checked.write_text(page.replace("</body>", f"<script>{CHECK_JS}</script>\n</body>"), encoding="utf-8")
    dom = run_chromium(chromium, ["--dump-dom", checked.as_uri()], workdir)
    found = re.search(rf'<script type="application/json" id="{MARKER}">(.*?)</script>', dom, re.S)
    assert found, f"the checking script left no result in the rendered DOM of {report} ({len(dom)} characters)"
    result = json.loads(found.group(1))
    # A copy without the checking script, for a human: the first 1600 px: title and summary.
    shown = workdir / "report.html"
    shutil.copyfile(report, shown)
    screenshot = workdir / "summary.png"
    run_chromium(chromium, [f"--screenshot={screenshot}", shown.as_uri()], workdir)
    result["screenshot"] = str(screenshot)
    return result


@pytest.fixture(scope="module", params=REPORTS, ids=lambda p: str(p.relative_to(ROOT)))
def rendered(request, tmp_path_factory):
    """(path of the report, what Chromium saw); one browser run per report for all tests."""
    workdir = tmp_path_factory.mktemp("browser")
    return request.param, render(request.param, workdir)


def test_a_committed_report_exists_to_render():
    assert REPORTS and REPORTS[0] == ROOT / "paper" / "reproduction.html"


def test_every_image_decodes(rendered):
    report, seen = rendered
    assert seen["images"], f"{report}: no <img> at all"
    broken = [i for i in seen["images"] if not i["complete"] or i["natural_width"] <= 0 or i["natural_height"] <= 0]
    assert not broken, f"{report}: {len(broken)} of {len(seen['images'])} images do not decode: {broken}"
    assert all(i["width"] > 0 for i in seen["images"]), f"{report}: an image is laid out with zero width"


def test_every_internal_link_resolves(rendered):
    report, seen = rendered
    internal = [link for link in seen["links"] if link["href"].startswith("#")]
    assert internal, f"{report}: no internal links (the summary links each item to its section)"
    dangling = [link for link in internal if not link["target_exists"]]
    assert not dangling, f"{report}: internal links without a target id: {dangling}"
    # A self-contained page may link to the web, but not to files beside it.
    relative = [link["href"] for link in seen["links"]
                if not link["href"].startswith("#") and not re.match(r"^[a-z][a-z0-9+.-]*:", link["href"])]
    missing = [h for h in relative if not (report.parent / h.split("#")[0]).exists()]
    assert not missing, f"{report}: links to files that do not exist beside it: {missing}"


def test_summary_table_is_visible(rendered):
    report, seen = rendered
    summary = seen.get("summary")
    assert summary, f"{report}: no table under the heading id='summary'"
    assert summary["display"] != "none" and summary["visibility"] == "visible" and float(summary["opacity"]) > 0
    assert summary["width"] > 100 and summary["height"] > 50 and summary["rows"] > 2, summary
    # Reachable by scrolling: inside the document box, not pushed off to the left or top.
    assert summary["top"] >= 0 and summary["left"] >= 0, summary
    assert summary["top"] + summary["height"] <= seen["scroll_height"] + 1, summary
    assert summary["left"] + summary["width"] <= seen["scroll_width"] + 1, summary
    assert pathlib.Path(seen["screenshot"]).stat().st_size > 10000, "screenshot of the summary is empty"


# ----------------------------------------------------------------------------- readability
PLACEHOLDER = re.compile(r"^[\s–—\-…]*$")


def cell_kind(text):
    """'number' for numeric cells (values, ± intervals, σ distances, ranges, lists of numbers),
    'text' for cells with words, None for empty or placeholder cells ('–')."""
    if PLACEHOLDER.match(text):
        return None
    bare = re.sub(r"s\.e\.", "", text)
    bare = re.sub(r"(?<=\d)e(?=[+\-−]?\d)", "", bare)  # exponent of 3.05e-4
    letters = [c for c in bare if c.isalpha() and c != "σ"]
    if not letters and any(c.isdigit() for c in bare):
        return "number"
    return "text" if letters else None


def column_kinds(table):
    """Per column: 'number' or 'text' where every filled cell is of that kind, else None."""
    width = max((len(r) for r in table["rows"]), default=0)
    kinds = []
    for j in range(width):
        seen = {cell_kind(r[j]["text"]) for r in table["rows"] if j < len(r)} - {None}
        kinds.append(seen.pop() if len(seen) == 1 else None)
    return kinds


VERDICT_WORD = re.compile(r"\b(agrees|differs|questioned)\b")


def has_mark(cell):
    """A verdict mark: the text starts with a symbol (✓, ✗, ?, ⚠ …) or a ::before content."""
    starts_with_symbol = bool(cell["text"]) and not (cell["text"][0].isalnum())
    before = any(c["before"] not in ("none", "normal", '""', "") for c in cell["colours"])
    return starts_with_symbol or before


def colour_signature(cell, seen):
    """The colours in a cell that differ from the page's text colour and background."""
    plain = {seen["body_color"], seen["body_background"], "rgba(0, 0, 0, 0)", "transparent"}
    sig = set()
    for c in cell["colours"]:
        sig |= {c["color"], c["background"]} - plain
    return frozenset(sig)


def test_tables_align_text_left_numbers_right_and_verdicts_stand_out(rendered):
    report, seen = rendered
    wrong = []
    for table in seen["tables"]:
        for j, kind in enumerate(column_kinds(table)):
            if kind is None:
                continue
            want = "left" if kind == "text" else "right"
            bad = [r[j]["text"][:30] for r in table["rows"] if j < len(r) and cell_kind(r[j]["text"])
                   and r[j]["align"] != want]
            if bad:
                name = table["head"][j] if j < len(table["head"]) else j
                wrong.append(f"table {table['index']} ({table['heading']}) column {name!r} is {kind}, "
                             f"{len(bad)} cells not {want}-aligned, e.g. {bad[0]!r}")
    assert not wrong, f"{report}:\n" + "\n".join(wrong)

    summary = next(t for t in seen["tables"] if t["is_summary"])
    col = next(j for j, h in enumerate(summary["head"]) if h.lower().startswith("verdict"))
    verdicts = [r[col] for r in summary["rows"] if VERDICT_WORD.search(r[col]["text"])]
    assert verdicts, "no verdict says agrees / differs / questioned"
    plain = [v["text"][:50] for v in verdicts if not has_mark(v) or not colour_signature(v, seen)]
    assert not plain, f"{report}: verdicts without a mark and a colour: {plain}"
    # Grouped by the mark in front (a questioned verdict may also say "agrees" or "differs"):
    # different marks must not share a colour.
    by_mark = {}
    for v in verdicts:
        by_mark.setdefault(v["text"].lstrip()[:1], set()).add(colour_signature(v, seen))
    marks = sorted(by_mark)
    for i, a in enumerate(marks):
        for b in marks[i + 1:]:
            assert not by_mark[a] & by_mark[b], f"verdicts marked {a} and {b} share a colour"


# ----------------------------------------------------------------------------- named files
REPO_PATH = re.compile(r"<code>((?:workflow|config|src|scripts|docs|tests|bench)/[^<\s]+)</code>")


@pytest.mark.parametrize("report", REPORTS, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_repository_file_the_report_names_exists(report):
    named = set(REPO_PATH.findall(report.read_text(encoding="utf-8")))
    assert named, f"{report} names no repository file"
    missing = sorted(p for p in named if not (ROOT / p).exists())
    assert not missing, f"{report} names files that do not exist: {missing}"


# ----------------------------------------------------------------------------- the docs site
DOCS_INDEX = ROOT / "build" / "docs" / "html" / "index.html"
DOCS_PAGES = ["getting-started.html", "physics.html", "config.html", "output.html", "python.html", "api.html",
              "tutorial-page.html", "workflow.html", "performance.html"]


def test_the_docs_site_renders_in_chromium(tmp_path):
    required = os.environ.get("GRANBOLTZ_REQUIRE_BROWSER") == "1"
    if not DOCS_INDEX.is_file():
        message = f"{DOCS_INDEX.relative_to(ROOT)} not built (make docs): the browser test of the docs did not run"
        if required:
            pytest.fail(message + "; GRANBOLTZ_REQUIRE_BROWSER=1 requires it")
        pytest.skip(message)
    chromium = find_chromium()
    if chromium is None:
        message = ("Chromium not installed: the browser test of the docs did not run "
                   "(install it with `bash scripts/install-deps.sh --with-browser`)")
        if required:
            pytest.fail(message + "; GRANBOLTZ_REQUIRE_BROWSER=1 requires it")
        pytest.skip(message)
    dom = run_chromium(chromium, ["--dump-dom", DOCS_INDEX.as_uri()], tmp_path)
    title = re.search(r"<title>(.*?)</title>", dom, re.S)
    assert title and "granboltz" in title.group(1), f"title of {DOCS_INDEX}: {title and title.group(1)!r}"
    text = re.sub(r"<[^>]+>", " ", re.sub(r"<(script|style)\b.*?</\1>", " ", dom, flags=re.S))
    text = re.sub(r"\s+", " ", text)
    for words in ("Boltzmann", "Getting started", "Python API reference", "Reproducing the papers"):
        assert words in text, f"{DOCS_INDEX} as rendered does not say {words!r}"
    hrefs = set(re.findall(r'href="([^"#?]+\.html)', dom))
    missing = [page for page in DOCS_PAGES if page not in hrefs]
    assert not missing, f"{DOCS_INDEX} does not link to {missing}"
    broken = sorted(h for h in hrefs if "://" not in h and not (DOCS_INDEX.parent / h).is_file())
    assert not broken, f"{DOCS_INDEX} links to pages that do not exist: {broken}"


def test_the_docs_site_documents_every_public_module():
    """A module that could not be imported when the site was built (granboltz.lib.inprocess without the
    extension) is left out of the API pages silently; the site must not be published that way."""
    if not DOCS_INDEX.is_file():
        if os.environ.get("GRANBOLTZ_REQUIRE_BROWSER") == "1":
            pytest.fail(f"{DOCS_INDEX.relative_to(ROOT)} not built (make docs); GRANBOLTZ_REQUIRE_BROWSER=1 requires it")
        pytest.skip(f"{DOCS_INDEX.relative_to(ROOT)} not built (make docs)")
    package = ROOT / "src" / "python"
    modules = sorted(".".join(p.relative_to(package).with_suffix("").parts).removesuffix(".__init__")
                     for p in (package / "granboltz").rglob("*.py")
                     if not any(part.startswith("_") and part != "__init__.py" for part in p.relative_to(package).parts)
                     # an old module path kept as a one-line alias is documented under its new one
                     and "# alias for a release" not in p.read_text())
    pages = DOCS_INDEX.parent / "_generated" / "api"
    missing = [m for m in modules if not (pages / f"{m}.html").is_file()]
    assert not missing, f"the docs site has no API page for {missing} (built before `make build`?)"
