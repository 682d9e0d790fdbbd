"""The workflow scripts as Snakemake runs them (script: directive), on synthetic inputs."""

import csv
import json

import numpy as np
import pytest
import yaml

PUBLISHED_COLUMNS = ["n", "E_max", "CF", "V_inf"]  # columns of GRW05 Table 1


def test_table_script_writes_grw05_table1_with_known_answers(fake_run, run_script, tmp_path):
    eps = {64: 0.08, 256: 0.02, 1024: 0.005, 4096: 0.00125}
    runs = [fake_run(n, eps=e, eps_centred=e / 4) for n, e in eps.items()]
    out = tmp_path / "tables" / "grw05_table1.csv"
    log = run_script("grw05_convergence_table.py", input={"runs": runs[::-1]}, output={"csv": str(out)})
    with open(out) as f:
        rows = list(csv.DictReader(f))
    assert list(rows[0])[: len(PUBLISHED_COLUMNS) + 1] == ["n", "N", "E_max", "CF", "V_inf"]
    assert {"E_max_ci", "Conf_end", "E_max_centred"} <= set(rows[0])
    assert [int(r["n"]) for r in rows] == list(eps)
    np.testing.assert_allclose([float(r["E_max"]) for r in rows], list(eps.values()), rtol=1e-3)
    assert rows[0]["CF"] == ""
    np.testing.assert_allclose([float(r["CF"]) for r in rows[1:]], 4.0, rtol=1e-3)
    np.testing.assert_allclose([float(r["E_max_centred"]) for r in rows], np.array(list(eps.values())) / 4,
                               rtol=1e-3)
    assert all(float(r["V_inf"]) == 0.0 for r in rows)
    assert "n=4096" in log
    assert sorted(p.name for p in out.parent.iterdir()) == ["grw05_table1.csv"]  # no temp files


def test_table_script_fails_without_output_on_bad_input(fake_run, run_script, tmp_path):
    V = np.full((33, 3), np.nan)
    out = tmp_path / "grw05_table1.csv"
    with pytest.raises(ValueError):
        run_script("grw05_convergence_table.py", input={"runs": [fake_run(64, V=V)]}, output={"csv": str(out)})
    assert not out.exists()


def _is_png(path, min_bytes=10_000):
    return path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and path.stat().st_size > min_bytes


def test_band_figure_script_writes_png_pdf_and_summary(fake_run, run_script, tmp_path):
    runs = [fake_run(n, eps=1.0 / n) for n in (64, 256, 1024, 4096)]
    png, pdf, summary = tmp_path / "grw05_fig1.png", tmp_path / "grw05_fig1.pdf", tmp_path / "fig1.json"
    run_script("temperature_bands.py", input={"runs": runs},
               output={"png": str(png), "pdf": str(pdf), "summary": str(summary)}, params={"t_range": [2.0, 8.0]})
    assert _is_png(png) and pdf.read_bytes()[:5] == b"%PDF-"
    import matplotlib.image

    height, width = matplotlib.image.imread(str(png)).shape[:2]
    assert width > height > 500  # 2 x 2 panels, landscape
    # the fake runs have ci = 0.01 T: the analytic curve is inside the band where 1/n <= 0.01
    inside = json.loads(summary.read_text())["numbers"]["inside"]
    assert inside["64"] == [0, 25] and inside["256"] == [25, 25] and "25/25 (n = 4096)" in json.loads(
        summary.read_text())["short"]


def test_curve_histogram_tail_and_crit_figures(fake_run, run_script, tmp_path):
    from conftest import add_moments, write_fake_histogram_run, write_fake_scheme_run

    def outputs(name):
        return {"png": str(tmp_path / f"{name}.png"), "pdf": str(tmp_path / f"{name}.pdf"),
                "summary": str(tmp_path / f"{name}.json")}

    runs = [fake_run(n, eps=1.0 / n) for n in (64, 256, 1024)]
    run_script("temperature_curves.py", input={"runs": runs}, output=outputs("fig3"), params={"t_range": [0.0, 8.0]})
    summary = json.loads((tmp_path / "fig3.json").read_text())
    assert summary["numbers"]["gaps"][0] > summary["numbers"]["gaps"][1] > 0 and "from above" in summary["ours"]
    hist = str(write_fake_histogram_run(tmp_path / "h.h5", lam=1.0, R=16.0, b=1.5))
    run_script("histograms.py", input={"runs": [hist]}, output=outputs("fig4"),
               params={"left": [0.0, 10.0], "right": [2.0, 10.0]})
    tails = {"k0": 1, "min_count": 1, "histogram": "density", "fit_window": [2.0, 3.0]}
    run_script("tail_plot.py", input={"runs": [hist]}, output=outputs("fig6"),
               params={"tails": tails, "guide_intercept": -3.0, "example": 8})
    assert json.loads((tmp_path / "fig6.json").read_text())["numbers"]["b"] == pytest.approx(1.5, rel=1e-9)
    crit = [str(add_moments(write_fake_scheme_run(tmp_path / f"{s}.h5", 4096, s, 32), crit_value=c))
            for s, c in (("euler", 0.10), ("strang", 0.12))]
    crit.insert(0, str(add_moments(fake_run(4096), crit_value=0.12)))
    run_script("crit_curves.py", input={"runs": crit}, output=outputs("rw05_fig4"), params={"label": "scheme"})
    ends = json.loads((tmp_path / "rw05_fig4.json").read_text())["numbers"]["crit_end"]
    assert ends["Euler splitting"][0] == pytest.approx(0.10) and ends["no-splitting"][0] == pytest.approx(0.12)
    for name in ("fig3", "fig4", "fig6", "rw05_fig4"):
        assert _is_png(tmp_path / f"{name}.png", 5_000) and (tmp_path / f"{name}.pdf").exists()


def test_write_run_config_script_writes_the_params(run_script, tmp_path):
    run = {"model": "dsmc", "seed": 7, "ensembles": 10, "dsmc": {"particles": 64, "alpha": 0.5}}
    out = tmp_path / "run.yaml"
    run_script("write_run_config.py", output={"yaml": str(out)}, params={"run": run})
    assert yaml.safe_load(out.read_text()) == run


def _rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))




def published_columns(name):
    from conftest import ROOT

    with open(ROOT / "config" / "published" / f"{name}.csv") as f:
        return next(csv.reader(f))


def test_rw05_table_scripts_carry_the_published_columns(fake_run, run_script, tmp_path):
    from conftest import write_fake_scheme_run

    runs = [fake_run(n, eps=5.4 / n) for n in (16, 64, 256)]
    out = tmp_path / "rw05_table1.csv"
    run_script("rw05_convergence_table.py", input={"runs": runs}, output={"csv": str(out)})
    rows = _rows(out)
    assert list(rows[0])[:7] == published_columns("rw05_table1")
    np.testing.assert_allclose([float(r["E_end"]) for r in rows], [5.4 / 16, 5.4 / 64, 5.4 / 256], rtol=1e-3)
    euler = [str(write_fake_scheme_run(tmp_path / f"e{K}.h5", 4096, "euler", K)) for K in (4, 8)]
    strang = [str(write_fake_scheme_run(tmp_path / f"s{K}.h5", 4096, "strang", K)) for K in (8, 4)]
    out = tmp_path / "rw05_table2.csv"
    run_script("rw05_timestep_table.py", input={"euler": euler, "strang": strang}, output={"csv": str(out)},
               params={"dt_unit": 8.0})
    rows = _rows(out)
    assert list(rows[0])[:5] == published_columns("rw05_table2") and [r["K"] for r in rows] == ["4", "8"]
    assert float(rows[1]["CF_euler"]) == pytest.approx(0.931 / 0.4223, rel=2e-3)


@pytest.mark.parametrize("name,layout,schemes", [
    ("rw05_table3_euler", "steps", [("euler", 32), ("euler", 256)]),
    ("rw05_table4_strang", "steps", [("strang", 8), ("strang", 16)]),
    ("rw05_table5_nosplit", "single", [("nosplit", None)]),
    ("rw05_table6", "methods", [("nosplit", None), ("strang", 32), ("euler", 32)]),
])
def test_steady_table_script_writes_each_layout(run_script, tmp_path, name, layout, schemes):
    from conftest import write_fake_steady_run

    beta = 37.5 if layout == "methods" else 1.0
    runs = [str(write_fake_steady_run(tmp_path / f"{s}{K}.h5", 65536, s, K, T_inf=2.7, wall=2.0 if K else 1.0,
                                      beta=beta)) for s, K in schemes]
    nosplit = str(write_fake_steady_run(tmp_path / "ref.h5", 65536, wall=1.0, beta=beta))
    out = tmp_path / f"{name}.csv"
    run_script("steady_table.py", input={"runs": runs, "nosplit": [nosplit]}, output={"csv": str(out)},
               params={"layout": layout, "dt_unit": 8.0})
    rows = _rows(out)
    columns = published_columns(name)
    assert list(rows[0])[:len(columns)] == columns
    if layout == "methods":
        assert [r["method"] for r in rows] == ["euler", "strang", "nosplit"]
        assert float(rows[0]["Error"]) == pytest.approx(100 - 2.7)
    else:
        assert all(float(r["Error"]) == pytest.approx(2.7 - 8 / 3, rel=1e-3) for r in rows)
        assert [float(r["CPU"]) for r in rows] == [2.0] * len(rows) or layout == "single"


def test_effort_and_replica_scripts(run_script, tmp_path):
    from conftest import write_fake_steady_run

    n = 65536
    n_coll = 2 * (n - 1) * 136
    runs = [str(write_fake_steady_run(tmp_path / "n.h5", n, events=(n_coll, 0, 2 * n_coll + 68 * n))),
            str(write_fake_steady_run(tmp_path / "e.h5", n, "euler", 32, events=(n_coll, 0, 544 * n)))]
    out = tmp_path / "rw05_effort.csv"
    run_script("rw05_effort.py", input={"runs": runs + runs[:1]}, output={"csv": str(out)},
               params={"dt_unit": 8.0, "steady_from": 8.0})
    rows = _rows(out)
    assert [r["scheme"] for r in rows] == ["nosplit", "euler"]  # duplicates removed
    assert int(rows[0]["N_coll"]) == int(rows[0]["N_coll_model"]) == round(n_coll)
    assert float(rows[1]["kick_ratio"]) == 1.0
    reps = [str(write_fake_steady_run(tmp_path / f"r{i}.h5", n, T_inf=2.667 + 0.001 * i)) for i in range(3)]
    out = tmp_path / "reps.csv"
    run_script("steady_replicas.py", input={"nosplit": reps, "euler": reps[:2]}, output={"csv": str(out)},
               params={"dt_unit": 8.0})
    rows = _rows(out)
    assert len(rows) == 2 and float(rows[0]["T_inf_sd"]) == pytest.approx(0.001)


def test_tail_exponent_script_recovers_b(run_script, tmp_path):
    from conftest import write_fake_histogram_run

    runs = {f"ex{ex}": [str(write_fake_histogram_run(tmp_path / f"{ex}.h5", lam=lam, b=1 + lam / 2))]
            for ex, lam in ((7, 0.0), (8, 1.0), (9, 0.5))}
    out, windows = tmp_path / "grw05_tail_exponents.csv", tmp_path / "grw05_tail_windows.csv"
    tails = {"k0": 1, "min_count": 1, "histogram": "density", "fit_window": [2.0, 3.0],
             "windows": [[1.5, 2.5], [2.0, 3.0]]}
    tails["local"] = {"pool_min_count": 400, "half_width": 4, "step": 2, "far_ci": 0.15, "tail_from": 0.01,
                      "paper_window": [4.25, 4.6]}
    local = []
    for ex in (7, 8, 9):  # the local-exponent figures, whose summaries feed the table
        names = {k: str(tmp_path / f"local{ex}.{k}") for k in ("png", "pdf")}
        names["summary"] = str(tmp_path / f"local{ex}.json")
        run_script("tail_local.py", input={"runs": runs[f"ex{ex}"]}, output=names,
                   params={"tails": tails, "example": ex})
        assert _is_png(tmp_path / f"local{ex}.png", 5_000)
        local.append(names["summary"])
    tails["swpm"] = {"kappa": 0.25, "max_particles": 2000, "particles": 1000, "ensembles": 8, "rows": 1,
                     "duration": 2.0, "reduction": "energy", "radius": {"ex7": 40.0, "ex8": 40.0, "ex9": 40.0},
                     "split_radius": {"ex7": 4.0, "ex8": 4.0, "ex9": 4.0}, "max_rel_ci": 0.3}
    swpm = []
    for ex, lam in ((7, 0.0), (8, 1.0), (9, 0.5)):  # the weighted-particle figures, on the same histograms
        names = {k: str(tmp_path / f"swpm{ex}.{k}") for k in ("png", "pdf")}
        names["summary"] = str(tmp_path / f"swpm{ex}.json")
        steady = [str(write_fake_histogram_run(tmp_path / f"s{ex}.h5", lam=lam, b=1 + lam / 2, steady=True))]
        run_script("tail_swpm.py", input={"swpm": steady, "constant": runs[f"ex{ex}"]}, output=names,
                   params={"tails": tails, "example": ex})
        assert _is_png(tmp_path / f"swpm{ex}.png", 5_000)
        swpm.append(names["summary"])
    # the importance check: two runs of one steady histogram agree; a steeper tail in the check differs
    for b_check, agrees in ((1.0, True), (2.0, False)):
        check = [str(write_fake_histogram_run(tmp_path / f"c{b_check}.h5", b=b_check, steady=True))]
        names = {k: str(tmp_path / f"check{b_check}.{k}") for k in ("png", "pdf")}
        names["summary"] = str(tmp_path / f"check{b_check}.json")
        split = {"radius": 4.0, "rate": 0.5, "power": 1.0, "interval": 0.01, "max_radius": 40.0}
        run_script("tail_swpm_check.py", input={"theory": [str(tmp_path / "s7.h5")], "check": check}, output=names,
                   params={"tails": tails, "example": 7, "theory_split": split,
                           "check_split": {**split, "power": 1.25}})
        assert _is_png(tmp_path / f"check{b_check}.png", 5_000)
        with open(names["summary"]) as f:
            summary = json.load(f)
        assert summary["numbers"]["reached"] is agrees, summary["ours"]
    run_script("tail_exponents.py", input={**runs, "local": local, "swpm": swpm},
               output={"csv": str(out), "windows": str(windows)}, params={"tails": tails})
    rows = _rows(out)
    for r in rows:  # the weighted-particle columns; both runs are the same histogram, so both depths agree
        assert float(r["depth_swpm"]) == float(r["depth_constant"]) and 0 < float(r["depth_swpm"]) < 1e-5
        assert float(r["b_swpm"]) == pytest.approx(float(r["theory_b"]), abs=0.05) and float(r["b_swpm_ci"]) > 0
    assert list(rows[0])[:7] == ["example", "kernel", "lambda", "theory_b", "b", "b_stderr", "fit_window"]
    for r in rows:  # exact histograms (eq. 38 with b = theory): b to the 6 digits of the CSV
        assert float(r["b"]) == pytest.approx(float(r["theory_b"]), rel=1e-5) and float(r["b_stderr"]) < 1e-6
        # density exp(-a ((k - 1) h)^b), constant per shell: b(r) and a close to b and a = 0.5
        assert float(r["b_local_far"]) == pytest.approx(float(r["theory_b"]), abs=0.03)
        assert float(r["a_fit"]) == pytest.approx(0.5, rel=0.05) and float(r["r_far"]) > 0
    assert [float(r["a_theory"]) for r in rows] == pytest.approx([0.7303, 0.4869, 0.5842], abs=1e-4)
    assert len(_rows(windows)) == 3 * 2 * 2


def test_latex_script_writes_a_booktabs_table(run_script, tmp_path):
    src = tmp_path / "grw05_table1.csv"
    src.write_text("n,E_max,kernel\n64,0.0895,hard_spheres\n")
    out = tmp_path / "grw05_table1.tex"
    run_script("latex_table.py", input={"csv": str(src)}, output={"tex": str(out)})
    text = out.read_text()
    assert text.startswith("% generated by rule table_tex") and r"\toprule" in text and r"hard\_spheres" in text
