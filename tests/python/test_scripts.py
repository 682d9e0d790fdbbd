"""The workflow scripts as Snakemake runs them (script: directive), on synthetic inputs."""

import csv

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


def test_figure_script_writes_png_and_pdf(fake_run, run_script, tmp_path):
    runs = [fake_run(n, eps=1.0 / n) for n in (64, 256, 1024, 4096)]
    png, pdf = tmp_path / "grw05_fig1.png", tmp_path / "grw05_fig1.pdf"
    run_script("grw05_temperature_bands.py", input={"runs": runs}, output={"png": str(png), "pdf": str(pdf)},
               params={"t_range": [2.0, 8.0]})
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 10_000
    assert pdf.read_bytes()[:5] == b"%PDF-"
    import matplotlib.image

    height, width = matplotlib.image.imread(str(png)).shape[:2]
    assert width > height > 500  # 2 x 2 panels, landscape


def test_write_run_config_script_writes_the_params(run_script, tmp_path):
    run = {"model": "dsmc", "seed": 7, "ensembles": 10, "dsmc": {"particles": 64, "alpha": 0.5}}
    out = tmp_path / "run.yaml"
    run_script("write_run_config.py", output={"yaml": str(out)}, params={"run": run})
    assert yaml.safe_load(out.read_text()) == run
