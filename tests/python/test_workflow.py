"""The workflow as a whole: Snakemake parses it, validates the config and plans the right jobs."""

import re
import subprocess

import pytest
import yaml

from conftest import ROOT

SNAKEMAKE = ["/usr/bin/snakemake", "--snakefile", "workflow/Snakefile", "--cores", "2", "--nolock"]


def snakemake(*args, cwd=ROOT):
    return subprocess.run(SNAKEMAKE + list(args), cwd=cwd, capture_output=True, text=True, timeout=300)


def job_counts(stdout):
    """{rule: count} from the 'Job stats' table of a dry run."""
    block = stdout.split("Job stats:", 1)[1].split("\n\n", 1)[0]
    rows = re.finditer(r"^(\w+)\s+(\d+)\s+\d+\s+\d+\s*$", block, re.M)
    return {m[1]: int(m[2]) for m in rows if m[1] != "total"}


@pytest.mark.parametrize("profile,runs", [("quick", 4), ("paper", 5)])
def test_dry_run_plans_every_job(profile, runs):
    result = snakemake("--configfile", f"config/{profile}.yaml", "-n", "--forceall")
    assert result.returncode == 0, result.stderr + result.stdout
    counts = job_counts(result.stdout)
    assert counts == {"all": 1, "grw05_fig1": 1, "grw05_table1": 1, "grw05_run": runs, "grw05_run_config": runs}


@pytest.mark.parametrize("profile", ["quick", "paper"])
def test_dry_run_succeeds(profile):
    result = snakemake("--configfile", f"config/{profile}.yaml", "-n")
    assert result.returncode == 0, result.stderr + result.stdout


def test_workflow_refuses_a_bad_profile(tmp_path):
    config = yaml.safe_load((ROOT / "config" / "quick.yaml").read_text())
    config["grw05"]["ex3"]["alpha"] = 2.0
    bad = tmp_path / "bad.yaml"
    bad.write_text(yaml.safe_dump(config))
    result = snakemake("--configfile", str(bad), "-n")
    assert result.returncode != 0
    assert "alpha" in result.stderr + result.stdout


def test_run_configs_carry_the_parameters_and_distinct_seeds(tmp_path):
    targets = [f"results/grw05/ex3/N=10/n={n}/run.yaml" for n in (64, 256)]
    result = snakemake("--configfile", str(ROOT / "config" / "quick.yaml"), "--directory", str(tmp_path),
                       *targets)
    assert result.returncode == 0, result.stderr
    first, second = (yaml.safe_load((tmp_path / t).read_text()) for t in targets)
    assert first["ensembles"] == 10 and first["dsmc"]["particles"] == 64 and second["dsmc"]["particles"] == 256
    assert first["dsmc"]["kernel"] == {"lambda": 0, "C": 0.07957747154594767}
    assert first["seed"] != second["seed"]
    again = tmp_path / "again"
    snakemake("--configfile", str(ROOT / "config" / "quick.yaml"), "--directory", str(again), targets[0])
    assert yaml.safe_load((again / targets[0]).read_text()) == first  # reruns are identical
