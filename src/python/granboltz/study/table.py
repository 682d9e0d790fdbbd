"""Reading a parameter study (granboltz.study): Study(folder or study file), its points and
table() as a pandas DataFrame, one row per point: the grid keys, hash, and each run's steady
averages with their intervals (or the last row of its time series).

    study = Study("studies/scan")
    study.points        # [(hash, {grid key: value})] of the current grid (index.csv)
    study.table()       # DataFrame; runs missing or not sound raise StudyError (table(missing="skip") marks them)
"""

import copy
import csv
import io
import math
import pathlib

import numpy as np

from .folder import check_folder
from .grid import full_grid, replica_seeds
from .runs import identity_problem, not_regular
from .spec import cell_text, study_parser, canonical, expand, load_study, point_text, run_config, study_folder
from .safe_yaml import MAX_BYTES, StudyError, lstat, one_line, read_text
from ..theory import LAMBDA_P

_MAX_INDEX_BYTES = 64 * MAX_BYTES  # an index of MAX_POINTS points with long values fits


class Study:
    """A study folder (studies/<study>/) as run() wrote it. `path`: the folder, or the study file
    (its folder is studies/<study> under `into`, default the current directory).

        study.points     [(hash, {grid key: value})] of the current grid, in index order
        study.keys       the grid keys
        study.run_path(hash), study.config(hash)
        study.missing()  the points without a run file
        study.problems() {hash: what is wrong} for the points without a sound run of their own
        study.table()    pandas DataFrame, one row per point

    A run is sound when it is a regular file (a link is not followed) that read_run reads and
    whose stored config is its point's config as the simulator resolves it
    (granboltz.study.identity_problem).
    """

    def __init__(self, path, into=None):
        path = pathlib.Path(path)
        st = lstat(path)
        if st is not None and not path.is_dir():
            path = study_folder(load_study(path, max_points=None), into)
        self.folder = path.absolute()
        check_folder(self.folder)
        index = self.folder / "index.csv"
        if lstat(index) is None:
            raise StudyError(f"{self.folder}: not a study folder (no index.csv; run `python -m granboltz.study run` first)")
        text = read_text(index, "study index", follow=False, limit=_MAX_INDEX_BYTES)
        # The index must list the points of the study file as the folder holds it (study.yaml):
        # an index cut short or edited would drop or mislabel points without a word.
        spec = load_study(self.folder / "study.yaml", max_points=None, follow=False)
        expanded = expand(spec)
        points = [(h, values) for h, values, _ in expanded]
        grid = full_grid(spec)
        expected = [["hash", *grid]] + [[h, *(cell_text(values[k]) for k in grid)] for h, values in points]
        try:
            rows = list(csv.reader(io.StringIO(text, newline="")))
        except csv.Error as e:
            raise StudyError(f"{index}: not a study index ({one_line(e, 100)})") from None
        if rows != expected:
            line = next((i for i, (a, b) in enumerate(zip(rows, expected), start=1) if a != b),
                        min(len(rows), len(expected)) + 1)
            raise StudyError(f"{index}: does not list the points of {self.folder / 'study.yaml'} (line {line} differs): "
                             "run the study again to rewrite it")
        self.name = self.folder.name
        self.keys = list(grid)
        self.replicas = replica_seeds(spec)  # the seeds of the replica axis (grid key seed), or None
        self.points = points
        self._configs = {h: config for h, _, config in expanded}

    def __repr__(self):
        have = sum(not_regular(self.run_path(h)) is None for h, _ in self.points)
        return f"Study({self.name!r}: {len(self.points)} points over {', '.join(self.keys)}; {have} runs)"

    def config(self, h):
        """The config of the point `h`: the folder's study.yaml expanded (what run() writes to
        points/<h>.yaml; a run made from an edited point file is not the point's and is named
        by problems() and table())."""
        if h not in self._configs:
            raise StudyError(f"{self.folder}: {one_line(repr(h), 40)} is not a point of this study")
        return copy.deepcopy(self._configs[h])

    def run_path(self, h):
        return self.folder / "runs" / f"{h}.h5"

    def missing(self):
        """The hashes of the points without a run file (problems() also checks the files)."""
        return [h for h, _ in self.points if lstat(self.run_path(h)) is None]

    def _read(self, h):
        """(Run, None) for a sound run of the point `h`, else (None, what is wrong)."""
        from ..output.io import RunReadError
        from ..output.run import read_run
        from .runs import brief

        path = self.run_path(h)
        problem = not_regular(path)
        if problem:
            return None, problem
        try:
            r = read_run(path)
        except (RunReadError, OSError) as e:
            return None, f"damaged: {brief(e, path)}"
        config = self.config(h)
        expected = self._run_config(h, config)
        if isinstance(expected, str):
            return None, expected
        problem = identity_problem(config, r.config, r.shard, expected)
        return (None, problem) if problem else (r, None)

    def _run_config(self, h, config):
        """The point's run_config by the simulator's parser (None where there is none: then
        every value of the point's own config must be in its run), or why there is none."""
        if not hasattr(self, "_parse"):
            try:
                self._parse = study_parser()
            except StudyError:
                self._parse = None
        if self._parse is None:
            return None
        try:
            return run_config(self._parse(point_text(config), f"point {h}"))
        except (ValueError, RuntimeError, TypeError) as e:
            return f"its point is refused by the simulator ({one_line(' '.join(str(e).split()), 80)})"

    def problems(self):
        """{hash: what is wrong} of the points without a sound run: "missing", what is there
        instead of a regular file, "damaged: ..." (read_run's reason) or "the run of another
        point ..." (its stored config differs from the point's)."""
        return {h: p for h, _ in self.points for _, p in [self._read(h)] if p}

    def table(self, missing="raise", aggregate=None):
        """One row per point: the grid keys, hash, and the run's observables: its steady averages
        with their intervals where the run has them (steady_from), else the last row of its time
        series: temperature, temperature_ci, a2, a2_ci, a3, a3_ci (where the run has them), per
        species T_<name>, T_<name>_ci (and a2_<name>, a2_<name>_ci with dsmc.moments >= 2), per pair of species a < b T_<a>/T_<b> with its _ci, and for rough
        particles theta = T_rot/T with theta_ci: the ratios the simulator stores, with intervals from
        the measured covariance of the two temperatures (granboltz.output.ratios; files of simulators that
        did not store them: theta from the means, theta_ci NaN).
        Columns steady (bool) and time (the last observation time, NaN for steady rows).

        missing: "raise" (StudyError naming the points without a sound run: missing, damaged,
        of another point, or not a regular file) or "skip" (their rows keep only grid keys and
        hash, with missing = True; the column missing is there only then).

        With a replica axis (`replicas:` in the study file) the rows of one grid point's replicas
        are aggregated (aggregate=None or True; False: one row per replica, with its seed): per
        value column x its mean over the replicas, x_spread (their standard deviation) and x_ci,
        the interval of that mean from the replicas' spread, Student-t with R - 1 degrees of
        freedom at the level of lambda_p = 3.2 (99.86 %); and `replicas`, the number of replicas
        with a sound run. Independent seeds make the spread honest whatever correlations a
        column's own interval leaves out (a ratio's, or a steady average's)."""
        if missing not in ("raise", "skip"):
            raise ValueError(f"missing must be 'raise' or 'skip', not {missing!r}")
        import pandas as pd

        runs, problems = {}, {}
        for h, _ in self.points:
            runs[h], problem = self._read(h)
            if problem:
                problems[h] = problem
        if problems and missing == "raise":
            named = "; ".join(f"{h} {one_line(p, 70)}" for h, p in list(problems.items())[:3])
            more = f"; and {len(problems) - 3} more" if len(problems) > 3 else ""
            raise StudyError(f"{self.name}: {len(problems)} of {len(self.points)} points have no sound run "
                             f"({named}{more}): run the study (python -m granboltz.study run) to make them")
        rows = []
        for h, values in self.points:
            row = dict(values, hash=h)
            if h in problems:
                row["missing"] = True
            else:
                row.update(observables(runs[h]))
                if problems:
                    row["missing"] = False
            rows.append(row)
        frame = pd.DataFrame(rows)
        if self.replicas and aggregate is not False:
            return aggregate_replicas(frame, [k for k in self.keys if k != "seed"], self.points)
        return frame

    def plot(self, x, y, ax=None, theory=None, **table_options):
        """A quick look: column y of table() against column x, with y_ci as error bars where the
        table has it, and `theory` (a function of the x values) dashed. Returns the axes."""
        from ..output.frames import plot_columns

        return plot_columns(self.table(**table_options), x, y, ax=ax, theory=theory)


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
        if "a2" in sp_source:  # a ratio of the species' moments, its interval by the delta method
            row[f"a2_{name}"], row[f"a2_{name}_ci"] = _value(sp_source["a2"], steady)
    names = list(r.species or {})
    for i, a in enumerate(names):  # T_a/T_b of a mixture, stored with its interval (granboltz.output.ratios)
        for b in names[i + 1:]:
            if f"temperature_ratio/{a}_over_{b}" in source:
                row[f"T_{a}/T_{b}"], row[f"T_{a}/T_{b}_ci"] = _value(source[f"temperature_ratio/{a}_over_{b}"], steady)
    if "theta" in source:  # rough particles: T_rot/T with the simulator's interval (granboltz.output.ratios)
        row["theta"], row["theta_ci"] = _value(source["theta"], steady)
    elif "temperature_rotational" in source and "temperature" in source:
        # a file of a simulator that did not store theta: the ratio of the means, no honest interval
        row["theta"] = _value(source["temperature_rotational"], steady)[0] / _value(source["temperature"], steady)[0]
        row["theta_ci"] = float("nan")
    return row


# The two-sided level of the package's intervals: lambda_p standard errors (GRW05 §5.1).
_LEVEL = math.erf(LAMBDA_P / math.sqrt(2.0))
_NOT_VALUES = ("hash", "steady", "time", "missing", "seed")


def aggregate_replicas(frame, keys, points):
    """One row per grid point of a table with one row per replica (Study.table)."""
    import pandas as pd
    from scipy import stats

    if "missing" in frame.columns:
        frame = frame[~frame["missing"].astype(bool)]
    values = [c for c in frame.columns if c not in keys and c not in _NOT_VALUES and not c.endswith("_ci")]
    groups = {}
    for index, (h, point) in enumerate(points):
        groups.setdefault(tuple(canonical(point[k]) for k in keys), (point, []))[1].append(h)
    rows = []
    for point, hashes in groups.values():
        part = frame[frame["hash"].isin(hashes)]
        row = {k: point[k] for k in keys}
        r = len(part)
        row["replicas"] = r
        if "steady" in part.columns and r:
            row["steady"] = bool(part["steady"].all())
        for c in values:
            x = part[c].to_numpy(dtype=float) if r else np.array([])
            mean = float(x.mean()) if r else math.nan
            spread = float(x.std(ddof=1)) if r > 1 else math.nan
            ci = float(stats.t.ppf(0.5 + _LEVEL / 2, r - 1) * spread / math.sqrt(r)) if r > 1 else math.nan
            row[c], row[c + "_spread"], row[c + "_ci"] = mean, spread, ci
        rows.append(row)
    return pd.DataFrame(rows)

