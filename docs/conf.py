"""Sphinx configuration of the granboltz documentation (`make docs` -> build/docs/html/).

The .md pages are read by myst-parser as they are. Two pages are generated at build time into
docs/_generated/ (git-ignored):
- the Python API reference: one page per module of the package, as pkgutil finds them now, so a
  module added later (granboltz.simulate, granboltz.study, ...) is documented without editing this
  file, and a module that does not exist yet cannot break the build;
- the tutorial: docs/tutorial.ipynb converted to a Markdown page (its cells and any stored
  outputs), not executed (tests/python/test_tutorial.py executes it).
Docstrings are written as plain text, not reStructuredText: each one is rendered as RST when
docutils parses it without a complaint, and verbatim (a literal block) otherwise, so the build
can run with -W (warnings are errors)."""

import importlib
import inspect
import json
import os
import pathlib
import pkgutil
import sys

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(ROOT / "src" / "python"))
os.environ.setdefault("MPLBACKEND", "Agg")

import granboltz  # noqa: E402

project = "granboltz"
author = "the granboltz authors"
copyright = "the granboltz authors"
release = version = granboltz.__version__

extensions = ["myst_parser", "sphinx.ext.autodoc", "sphinx.ext.autosummary", "sphinx.ext.mathjax"]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
default_role = "literal"  # `name` in a docstring is code, as in the .md pages
root_doc = "index"
exclude_patterns = ["_build", "**/.ipynb_checkpoints", "_generated/tutorial.md"]
html_theme = "furo"
html_title = "granboltz documentation"
html_static_path = []
myst_enable_extensions = ["dollarmath"]
myst_heading_anchors = 4
suppress_warnings = []
autodoc_default_options = {"members": True, "undoc-members": False, "show-inheritance": True}
autodoc_member_order = "bysource"
autodoc_typehints = "signature"
autosummary_generate = False

GENERATED = HERE / "_generated"


# --------------------------------------------------------------------------- the API reference
def public_modules():
    """Every public module of the package (no name part starting with '_'), importable now."""
    names = ["granboltz"]
    for info in pkgutil.walk_packages(granboltz.__path__, "granboltz."):
        if any(part.startswith("_") for part in info.name.split(".")):
            continue
        try:
            module = importlib.import_module(info.name)
        except Exception as error:  # noqa: BLE001 - a module that cannot be imported is listed, not fatal
            print(f"conf.py: {info.name} is not importable ({error}); left out of the API pages")
            continue
        if module.__name__ != info.name:  # an old module path kept as an alias: documented under its new one
            continue
        names.append(info.name)
    return names


def defined_members(module):
    """Public functions and classes defined in `module` itself (as automodule :members: shows)."""
    out = []
    for name, obj in vars(module).items():
        if name.startswith("_") or not (inspect.isfunction(obj) or inspect.isclass(obj)):
            continue
        if getattr(obj, "__module__", None) == module.__name__:
            out.append(name)
    return out


# Names offered on the package itself, imported lazily or from a compiled/private module; each is
# documented where it is defined when that is a public module, else on the package page.
PACKAGE_NAMES = ["read_run", "RunReadError", "simulate", "Simulation", "Run", "Study", "study"]


def first_line(obj):
    """The first paragraph of obj's docstring, on one line."""
    doc = (inspect.getdoc(obj) or "").strip()
    return " ".join(doc.split("\n\n")[0].split())


def package_page(modules):
    lines = ["granboltz (the package)", "=" * 23, "", ".. module:: granboltz", "",
             "The names on the package itself; every module has its own page (below).", ""]
    referenced, direct = [], []
    for name in PACKAGE_NAMES:
        try:
            obj = getattr(granboltz, name)
        except Exception:  # noqa: BLE001 - not provided (yet): nothing to document
            continue
        if inspect.ismodule(obj):
            if obj.__name__ in modules:
                referenced.append(f"- ``granboltz.{name}``: the module :mod:`{obj.__name__}`")
            continue
        home = getattr(obj, "__module__", None)
        role = "class" if inspect.isclass(obj) else "func"
        if home in modules and home != "granboltz":
            target = f"{home}.{getattr(obj, '__qualname__', name)}"
            referenced.append(f"- ``granboltz.{name}``: :py:{role}:`{target}` — {first_line(obj)}")
        else:
            direct.append((name, role))
    lines += referenced + [""]
    for name, role in direct:
        directive = "autoclass" if role == "class" else "autofunction"
        lines += [f".. {directive}:: granboltz.{name}", ""]
        if role == "class":
            lines += ["   :members:", ""]
    # the sub-packages and the top-level modules; each sub-package's page lists its own modules
    lines += [".. toctree::", "   :maxdepth: 1", ""]
    lines += [f"   {m}" for m in modules if m.count(".") == 1]
    return "\n".join(lines) + "\n"


def module_page(name, modules):
    module = importlib.import_module(name)
    title = f"``{name}``"
    lines = [title, "=" * len(title), "", f".. automodule:: {name}", "   :no-members:", ""]
    members = defined_members(module)
    if members:
        lines += [".. currentmodule:: " + name, "", ".. autosummary::", ""]
        lines += [f"   {m}" for m in members] + [""]
        for m in members:
            obj = getattr(module, m)
            lines += [f".. auto{'class' if inspect.isclass(obj) else 'function'}:: {name}.{m}", ""]
            if inspect.isclass(obj):
                lines += ["   :members:", ""]
    if hasattr(module, "__path__"):  # a sub-package: the API reference of its modules below it
        subs = [m for m in modules if m.startswith(name + ".") and m.count(".") == name.count(".") + 1]
        if subs:
            lines += [".. toctree::", "   :maxdepth: 1", ""] + [f"   {s}" for s in subs] + [""]
    return "\n".join(lines) + "\n"


def write_if_changed(path, text):
    path.parent.mkdir(parents=True, exist_ok=True)
    if not path.exists() or path.read_text(encoding="utf-8") != text:
        path.write_text(text, encoding="utf-8")


# --------------------------------------------------------------------------- the tutorial page
def notebook_page(notebook):
    """docs/tutorial.ipynb as Markdown: markdown cells as they are, code cells as python blocks,
    stored text outputs as text blocks (the notebook is not executed here)."""
    nb = json.loads(notebook.read_text(encoding="utf-8"))
    out = []
    for cell in nb["cells"]:
        source = "".join(cell["source"]).rstrip()
        if cell["cell_type"] == "markdown":
            out.append(source)
        elif cell["cell_type"] == "code" and source:
            out.append("```python\n" + source + "\n```")
            for o in cell.get("outputs", []):
                text = "".join(o.get("text", "")) or "".join(o.get("data", {}).get("text/plain", ""))
                if text.strip():
                    out.append("```text\n" + text.rstrip() + "\n```")
    first, rest = out[0], out[1:]  # the notebook's title first, then where to get the notebook
    note = ("The notebook itself: {download}`tutorial.ipynb <tutorial.ipynb>` (run it with "
            "Jupyter, or as the test does: `/usr/bin/python3 -m pytest tests/python/test_tutorial.py`). "
            "This page shows its cells; it is not executed when the documentation is built.")
    return "\n\n".join([first, note] + rest) + "\n"


def generate(app, config):
    modules = public_modules()
    api = GENERATED / "api"
    write_if_changed(api / "granboltz.rst", package_page(modules))
    for m in modules:
        if m != "granboltz":
            write_if_changed(api / f"{m}.rst", module_page(m, modules))
    for stale in api.glob("*.rst"):
        if stale.stem not in modules:
            stale.unlink()
    notebook = HERE / "tutorial.ipynb"
    if notebook.exists():
        write_if_changed(GENERATED / "tutorial.md", notebook_page(notebook))


# --------------------------------------------------------------------------- plain-text docstrings
def clean_rst(text):
    """True when docutils parses `text` as reStructuredText without any message."""
    import io

    from docutils.core import publish_doctree

    stream = io.StringIO()
    try:
        publish_doctree(text, settings_overrides={"warning_stream": stream, "report_level": 1,
                                                  "halt_level": 5, "file_insertion_enabled": False,
                                                  "raw_enabled": False})
    except Exception:  # noqa: BLE001
        return False
    return stream.getvalue() == ""


def escape_rst(text):
    """`text` with the characters reStructuredText would read as markup escaped."""
    for c in "\\*_|`":
        text = text.replace(c, "\\" + c)
    return text


def docstring_as_text(app, what, name, obj, options, lines):
    """A docstring docutils would complain about: its first paragraph as text when that alone is
    clean (autosummary's one-line summary comes from it), the rest verbatim as a literal block."""
    if not lines or clean_rst("\n".join(lines)):
        return
    blank = next((i for i, line in enumerate(lines) if not line.strip()), len(lines))
    head, rest = lines[:blank], lines[blank:]
    if not clean_rst("\n".join(head)):
        escaped = [escape_rst(line.strip()) for line in head]  # the paragraph as plain text
        head = escaped if clean_rst("\n".join(escaped)) else []
        rest = lines[blank:] if head else lines
    body = [line for line in rest]
    while body and not body[0].strip():
        body.pop(0)
    literal = ["::", ""] + ["    " + line if line else "" for line in body] + [""] if body else []
    lines[:] = head + ([""] if head else []) + literal


def setup(app):
    app.connect("config-inited", generate)
    app.connect("autodoc-process-docstring", docstring_as_text)
