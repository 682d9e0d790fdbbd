#!/usr/bin/python3
"""The Python twin of check_layers.py: the sub-packages of src/python/granboltz/ are layers.

A module imports its own sub-package and lower layers only (the modules still at the top level,
entry points and the one-line aliases of old module paths, count as the top layer); no module
imports a private name (_x) from another module (the compiled extension _core excepted); and
the theory is pure: no file, no process, no verdict. Exit 1 with one line per violation.

    check_layers_python.py [PACKAGE]   (default: this repository's src/python/granboltz)
"""
import ast
import pathlib
import sys

LAYERS = {"_core": 0,         # the compiled extension: the simulator itself, imports nothing of the package
          "theory": 0,        # closed forms and exact results
          "output": 1,        # reading outputs
          "analysis": 2,      # estimators on arrays and runs
          "lib": 3,           # the simulator in this process
          "study": 4,         # parameter studies
          "reproduction": 5,  # the papers' tables and verdicts
          "report": 6,        # the reproduction report
          "": 9}              # the top level: the entry points and the one-line aliases
PURE = {"theory"}       # no files, processes or verdicts
IMPURE_MODULES = {"h5py", "yaml", "pandas", "matplotlib", "os", "pathlib", "io", "shutil", "subprocess", "tempfile"}


def layer_of(parts):
    """The sub-package of a module given by its dotted parts below granboltz ('' for the top level)."""
    return parts[0] if len(parts) > 1 and parts[0] in LAYERS else ""


def imports(tree, parts, is_package):
    """(line, imported module parts below granboltz or None for outside, names) of every import."""
    here = parts if is_package else parts[:-1]
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                top = a.name.split(".")
                yield node.lineno, top[1:] if top[0] == "granboltz" else None, top[0], []
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = here[:len(here) - (node.level - 1)] if node.level > 1 else here
                target = list(base) + (node.module.split(".") if node.module else [])
                yield node.lineno, target, None, [a.name for a in node.names]
            else:
                top = (node.module or "").split(".")
                yield node.lineno, top[1:] if top[0] == "granboltz" else None, top[0], [a.name for a in node.names]


def main(package):
    package, bad = pathlib.Path(package), []
    for path in sorted(package.rglob("*.py")):
        rel = path.relative_to(package).with_suffix("").parts
        is_package = rel[-1] == "__init__"
        parts = rel[:-1] if is_package else rel
        layer, text = layer_of(parts), path.read_text()
        tree = ast.parse(text)
        where = f"{path.relative_to(package.parent)}"
        for line, target, outside, names in imports(tree, parts, is_package):
            if target is None:
                if layer in PURE and outside in IMPURE_MODULES:
                    bad.append(f"{where}:{line}: the {layer} layer is pure but imports {outside}")
                continue
            # `from . import x` imports the module x of the package
            targets = [target + [n] if not target or (package.joinpath(*target, n + ".py").exists()
                                                      or package.joinpath(*target, n).is_dir()) else target
                       for n in names] or [target]
            for t in targets:
                to = layer_of(t) if len(t) > 1 else (t[0] if t and t[0] in LAYERS else "")
                if to != layer and LAYERS[to] >= LAYERS[layer]:
                    bad.append(f"{where}:{line}: layer '{layer or 'top'}' imports granboltz.{'.'.join(t)} "
                               f"(layer '{to or 'top'}'), which is not below it")
            for n in names:
                if n.startswith("_") and not n.startswith("__") and n != "_core":
                    bad.append(f"{where}:{line}: imports the private name {n} from another module")
        if layer in PURE:
            for node in ast.walk(tree):
                if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "open":
                    bad.append(f"{where}:{node.lineno}: the {layer} layer is pure but opens a file")
                if isinstance(node, (ast.Name, ast.FunctionDef, ast.Attribute)):
                    name = getattr(node, "id", None) or getattr(node, "name", None) or getattr(node, "attr", "")
                    if "verdict" in name.lower():
                        bad.append(f"{where}:{node.lineno}: the {layer} layer is pure but has a verdict ({name})")
    for line in bad:
        print(line, file=sys.stderr)
    return 1 if bad else 0


if __name__ == "__main__":
    default = pathlib.Path(__file__).resolve().parent.parent / "src" / "python" / "granboltz"
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else default))
