"""`granboltz run` says in one line on stdout that it succeeded: the output's path, the wall time
and the values a user looks at first, read back from the output; nothing with -q."""

import re

from conftest import BASE, run_binary


def _run(tmp_path, config, *extra):
    out = tmp_path / "out.h5"
    result = run_binary("run", BASE / config, "--threads", "1", "-o", out, *extra,
                        capture_output=True, text=True)
    return out, result


def test_a_steady_run_prints_where_its_output_is_and_its_steady_values(tmp_path):
    out, result = _run(tmp_path, "dsmc.yaml", "--set", "dsmc.steady_from=0.2", "--set", "dsmc.moments=2")
    lines = result.stdout.splitlines()
    assert len(lines) == 1, result.stdout
    m = re.fullmatch(r"granboltz: wrote (.+) in ([0-9.e+-]+) s: steady T = ([0-9.e+-]+) ± ([0-9.e+-]+), "
                     r"a2 = (-?[0-9.e+-]+) ± ([0-9.e+-]+)", lines[0])
    assert m, lines[0]
    assert m.group(1) == str(out) and float(m.group(2)) > 0
    import h5py

    with h5py.File(out) as f:  # the printed numbers are the output's, rounded
        assert float(m.group(3)) == float(f"{f['steady/temperature/mean'][()]:.5g}")
        assert float(m.group(5)) == float(f"{f['steady/a2/mean'][()]:.5g}")


def test_other_runs_print_their_last_temperature_or_their_ratios(tmp_path):
    _, result = _run(tmp_path, "dsmc.yaml")
    assert re.fullmatch(r"granboltz: wrote .+ s: T\(t_end\) = [0-9.e+-]+ ± [0-9.e+-]+\n", result.stdout), result.stdout
    _, result = _run(tmp_path, "intruder.yaml")
    assert re.fullmatch(r"granboltz: wrote .+ s: temperature_ratio = [0-9.e+-]+ ± [0-9.e+-]+\n", result.stdout), result.stdout


def test_quiet_prints_nothing(tmp_path):
    _, result = _run(tmp_path, "dsmc.yaml", "-q")
    assert result.stdout == "" and result.stderr == ""
