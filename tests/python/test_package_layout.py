"""The package's shape: every public name documented, small modules, thin
workflow scripts, nothing heavy imported by `import granboltz`, and the golden-table check."""

import importlib
import inspect
import pkgutil
import subprocess
import sys

import granboltz
from conftest import ROOT

MODULES = [m.name for m in pkgutil.walk_packages(granboltz.__path__, "granboltz.")]


def test_every_public_name_has_a_docstring():
    undocumented = []
    for name in ["granboltz"] + MODULES:
        module = importlib.import_module(name)
        if not (module.__doc__ or "").strip():
            undocumented.append(name)
        for attr, obj in vars(module).items():
            if attr.startswith("_") or getattr(obj, "__module__", None) != name:
                continue
            if inspect.isfunction(obj) or inspect.isclass(obj):
                if not (obj.__doc__ or "").strip():
                    undocumented.append(f"{name}.{attr}")
    assert not undocumented, undocumented


def test_modules_and_scripts_are_small():
    long_modules = {p.name: n for p in (ROOT / "src" / "python").rglob("*.py")
                    if (n := len(p.read_text().splitlines())) > 300}
    long_scripts = {p.name: n for p in (ROOT / "workflow" / "scripts").glob("*.py")
                    if (n := len(p.read_text().splitlines())) > 85}
    assert not long_modules and not long_scripts, (long_modules, long_scripts)


def test_importing_the_package_stays_light():
    # the package and each of its sub-packages: their names are loaded on first use
    heavy = ("h5py", "matplotlib", "scipy", "numpy", "pandas", "yaml")
    for package in ("granboltz", "granboltz.theory", "granboltz.output", "granboltz.analysis", "granboltz.lib",
                    "granboltz.study", "granboltz.reproduction"):
        code = f"import sys, {package}; print(sorted(m for m in {heavy!r} if m in sys.modules))"
        out = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True,
                             env={"PYTHONPATH": str(ROOT / "src" / "python")}).stdout
        assert out.strip() == "[]", (package, out)


def test_check_tables_finds_one_changed_byte(tmp_path):
    golden, results = tmp_path / "golden", tmp_path / "results"
    golden.mkdir()
    results.mkdir()
    for d in (golden, results):
        (d / "t1.csv").write_text("n,E_max\n64,0.085\n")
        (d / "t1.tex").write_text("\\toprule\n")
    script = [sys.executable, str(ROOT / "tests" / "golden" / "check_tables.py"), str(results), str(golden)]
    ok = subprocess.run(script, capture_output=True, text=True)
    assert ok.returncode == 0 and "2 tables" in ok.stdout
    (results / "t1.csv").write_text("n,E_max\n64,0.086\n")
    (results / "extra.csv").write_text("x\n")
    bad = subprocess.run(script, capture_output=True, text=True)
    assert bad.returncode == 1
    assert "differs:" in bad.stderr and "+64,0.086" in bad.stderr and "not in the golden set" in bad.stderr
    (results / "t1.tex").unlink()
    assert "missing:" in subprocess.run(script, capture_output=True, text=True).stderr


def test_check_tables_ignores_only_the_measured_wall_times(tmp_path):
    golden, results = tmp_path / "golden", tmp_path / "results"
    for d, wall, T in ((golden, "1.11657", "2.93183"), (results, "1.2034", "2.93183")):
        d.mkdir()
        (d / "t3.csv").write_text(f"K,T_inf,CPU,CF_CPU,wall_seconds\n32,{T},1.15,,{wall}\n")
        (d / "t3.tex").write_text("% generated\n\\begin{tabular}{rrrrr}\n\\toprule\n"
                                  "$K$ & $T_\\infty$ & CPU & CF\\_CPU & wall\\_seconds \\\\\n\\midrule\n"
                                  f"32 & {T} & 1.15 & -- & {wall} \\\\\n\\bottomrule\n\\end{{tabular}}\n")
    script = [sys.executable, str(ROOT / "tests" / "golden" / "check_tables.py"), str(results), str(golden)]
    assert subprocess.run(script, capture_output=True, text=True).returncode == 0
    for name in ("t3.csv", "t3.tex"):  # the same change of a value that is not a wall time is caught
        path = results / name
        path.write_text(path.read_text().replace("2.93183", "2.93184"))
        out = subprocess.run(script, capture_output=True, text=True)
        assert out.returncode == 1 and f"differs: {path}" in out.stderr
        path.write_text(path.read_text().replace("2.93184", "2.93183"))
    (results / "t3.csv").write_text("K,T_inf,CPU,CF_CPU,wall_seconds\n32,2.93183,1.15,,\n")  # a time gone missing
    assert subprocess.run(script, capture_output=True, text=True).returncode == 1
