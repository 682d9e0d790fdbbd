"""Reading a parameter study (granboltz.study): Study(folder or study file), its points and
table() as a pandas DataFrame, one row per point: the grid keys, hash, and each run's steady
averages with their intervals (or the last row of its time series).

    study = Study("studies/scan")
    study.points        # [(hash, {grid key: value})] of the current grid (index.csv)
    study.table()       # DataFrame; missing runs raise StudyError (table(missing="skip") marks them)
"""

import csv
import pathlib

import yaml

from .study import StudyError, _get, load_study, study_folder


class Study:
    """A study folder (studies/<study>/) as run() wrote it. `path`: the folder, or the study file
    (its folder is studies/<study> under `into`, default the current directory).

        study.points   [(hash, {grid key: value})] of the current grid, in index order
        study.keys     the grid keys
        study.run_path(hash), study.config(hash)
        study.table()  pandas DataFrame, one row per point
    """

    def __init__(self, path, into=None):
        path = pathlib.Path(path)
        if path.is_file():
            path = study_folder(load_study(path), into)
        self.folder = path.absolute()
        index = self.folder / "index.csv"
        try:
            with open(index, newline="") as f:
                rows = list(csv.reader(f))
        except OSError:
            raise StudyError(f"{self.folder}: not a study folder (no index.csv; run `python -m granboltz.study run` first)") from None
        if not rows or not rows[0] or rows[0][0] != "hash":
            raise StudyError(f"{index}: not a study index (its first column must be hash)")
        self.name = self.folder.name
        self.keys = rows[0][1:]
        self.points = []
        for row in rows[1:]:
            h, config = row[0], self.config(row[0])
            self.points.append((h, {k: _get(config, k) for k in self.keys}))

    def __repr__(self):
        have = sum(self.run_path(h).is_file() for h, _ in self.points)
        return f"Study({self.name!r}: {len(self.points)} points over {', '.join(self.keys)}; {have} runs)"

    def config(self, h):
        path = self.folder / "points" / f"{h}.yaml"
        try:
            return yaml.safe_load(path.read_text())
        except OSError:
            raise StudyError(f"{path}: point file missing") from None

    def run_path(self, h):
        return self.folder / "runs" / f"{h}.h5"

    def missing(self):
        """The hashes of the points without a run."""
        return [h for h, _ in self.points if not self.run_path(h).is_file()]

    def table(self, missing="raise"):
        """One row per point: the grid keys, hash, and the run's observables: its steady averages
        with their intervals where the run has them (steady_from), else the last row of its time
        series: temperature, temperature_ci, a2, a2_ci, a3, a3_ci (where the run has them), per
        species T_<name>, T_<name>_ci, per pair of species a < b T_<a>/T_<b> with its _ci, and for rough
        particles theta = T_rot/T with theta_ci: the ratios the simulator stores, with intervals from
        the measured covariance of the two temperatures (granboltz.ratios; files of simulators that
        did not store them: theta from the means, theta_ci NaN).
        Columns steady (bool) and time (the last observation time, NaN for steady rows).

        missing: "raise" (StudyError naming the points without a run) or "skip" (their rows keep
        only grid keys and hash, with missing = True; the column missing is there only then)."""
        import pandas as pd

        from .run import read_run

        absent = self.missing()
        if absent and missing == "raise":
            raise StudyError(f"{self.name}: {len(absent)} of {len(self.points)} points have no run "
                             f"({', '.join(absent[:4])}{', ...' if len(absent) > 4 else ''}): run the study first")
        if missing not in ("raise", "skip"):
            raise ValueError(f"missing must be 'raise' or 'skip', not {missing!r}")
        rows = []
        for h, values in self.points:
            row = dict(values, hash=h)
            if h in absent:
                row["missing"] = True
            else:
                row.update(observables(read_run(self.run_path(h))))
                if absent:
                    row["missing"] = False
            rows.append(row)
        return pd.DataFrame(rows)


def _value(obs, steady):
    """(mean, ci) of an observable: the steady average, or the last row of the series."""
    if steady:
        return float(obs.mean), float(obs.ci)
    return float(obs.mean[-1]), float(obs.ci[-1])


def observables(r):
    """The table row of one Run (read_run): see Study.table."""
    steady = bool(r.steady) and "temperature" in r.steady
    source = r.steady if steady else r.observables
    row = {"steady": steady, "time": float("nan") if steady or r.time is None else float(r.time[-1])}
    for name in ("temperature", "a2", "a3"):
        if name in source:
            row[name], row[f"{name}_ci"] = _value(source[name], steady)
    for name, sp in (r.species or {}).items():
        sp_source = sp.steady if steady else sp.observables
        if "temperature" in sp_source:
            row[f"T_{name}"], row[f"T_{name}_ci"] = _value(sp_source["temperature"], steady)
    names = list(r.species or {})
    for i, a in enumerate(names):  # T_a/T_b of a mixture, stored with its interval (granboltz.ratios)
        for b in names[i + 1:]:
            if f"temperature_ratio/{a}_over_{b}" in source:
                row[f"T_{a}/T_{b}"], row[f"T_{a}/T_{b}_ci"] = _value(source[f"temperature_ratio/{a}_over_{b}"], steady)
    if "theta" in source:  # rough particles: T_rot/T with the simulator's interval (granboltz.ratios)
        row["theta"], row["theta_ci"] = _value(source["theta"], steady)
    elif "temperature_rotational" in source and "temperature" in source:
        # a file of a simulator that did not store theta: the ratio of the means, no honest interval
        row["theta"] = _value(source["temperature_rotational"], steady)[0] / _value(source["temperature"], steady)[0]
        row["theta_ci"] = float("nan")
    return row
