"""The DSMC runs behind the GRW05 and RW05 items, read as the table builders need them: the
temperature series of a run (DsmcRun), the radial histogram of a tail run, the steady-state
averages of RW05 §4.2, and Crit(t) of RW05 eq. (29) from the ensemble-mean moments.

(For a general-purpose reader of any granboltz output see granboltz.output.run.read_run.)
"""

from dataclasses import dataclass, field

import numpy as np

from ..analysis.moment_checks import crit_of_means  # noqa: F401 (its users import it from here too)
from ..output.io import open_run, read_config, read_dataset, read_finite, reading, run_attrs, text

# Temperature estimator behind the published error tables: phi(v) = |v|^2 / 3 (RW05 §4.1). Its
# exact finite-n bias matches the published E_max (about 5.7/n in GRW05 Example 3); the centred
# temperature (GRW05 eq. 13) is biased by only about 1/n and is reported alongside.
TEMPERATURE = "temperature_uncentred"
TEMPERATURE_CENTRED = "temperature"


@dataclass
class DsmcRun:
    """The observables of one DSMC run (granboltz HDF5 output) needed by the GRW05/RW05 items."""

    path: str
    config: dict  # the run config, as stored in the file's root attribute `config`
    n: int  # particles per ensemble
    N: int  # ensembles
    time: np.ndarray  # observation times t_m, [M+1]
    T: np.ndarray  # mean of the uncentred temperature estimator, [M+1]
    T_ci: np.ndarray  # its confidence half-width (GRW05 eq. 31, lambda_p = 3.2), [M+1]
    T_centred: np.ndarray  # mean of the centred temperature (GRW05 eq. 13), [M+1]
    T_centred_ci: np.ndarray
    V: np.ndarray  # mean bulk velocity (GRW05 eq. 12), [M+1, 3]
    crit: np.ndarray = None  # Crit(t) of RW05 eq. (29) per ensemble, averaged, [M+1]
    crit_ci: np.ndarray = None
    moments: dict = None  # ensemble means (and ci) of pressure_tensor, heat_flux, fourth_moment[, moment_4]
    attrs: dict = field(default_factory=dict)  # version, git_sha, wall_seconds

    @property
    def dsmc(self):
        """The run config's `dsmc` section."""
        return self.config["dsmc"]

    @property
    def scheme(self):
        """The time scheme: nosplit, euler or strang."""
        return self.dsmc.get("scheme", "nosplit")

    @property
    def dt(self):
        """Time step of a splitting scheme (t_end / steps); None for no-splitting."""
        return None if self.scheme == "nosplit" else self.dsmc["t_end"] / self.dsmc["steps"]


def read_dsmc(path):
    """Read one granboltz DSMC output file into a DsmcRun; refuse non-finite values."""
    with open_run(path) as f:
        config = read_config(f, path)
        crit = "crit/mean" in f
        names = ("pressure_tensor/mean", "heat_flux/mean", "fourth_moment/mean", "fourth_moment/ci")
        moments = {name: read_finite(f, name, path) for name in names} if all(n in f for n in names) else None
        if moments is not None and "moment_4/mean" in f:  # <|v - V|^4> (dsmc.moments >= 2)
            moments.update({name: read_finite(f, name, path) for name in ("moment_4/mean", "moment_4/ci")})
        return DsmcRun(
            path=str(path),
            config=config,
            n=int(config["dsmc"]["particles"]),
            N=int(f.attrs["ensembles"]),
            time=read_finite(f, "time", path),
            T=read_finite(f, f"{TEMPERATURE}/mean", path),
            T_ci=read_finite(f, f"{TEMPERATURE}/ci", path),
            T_centred=read_finite(f, f"{TEMPERATURE_CENTRED}/mean", path),
            T_centred_ci=read_finite(f, f"{TEMPERATURE_CENTRED}/ci", path),
            V=read_finite(f, "bulk_velocity/mean", path),
            crit=read_finite(f, "crit/mean", path) if crit else None,
            crit_ci=read_finite(f, "crit/ci", path) if crit else None,
            moments=moments,
            attrs=run_attrs(f),
        )


def read_histogram(path):
    """The radial histogram of a run (GRW05 eq. 37): dict with edges [K+1], mean and counts
    [M+1, K+1] (last shell = |v| >= R), time, n, N, config."""
    with open_run(path) as f:
        config = read_config(f, path)
        return {
            "edges": read_finite(f, "histogram/edges", path),
            "mean": read_finite(f, "histogram/mean", path),
            "counts": read_dataset(f, "histogram/counts", path),
            "time": read_finite(f, "time", path),
            "T": read_finite(f, f"{TEMPERATURE_CENTRED}/mean", path),
            "n": int(config["dsmc"]["particles"]),
            "N": int(f.attrs["ensembles"]),
            "config": config,
        }


def _batch_interval(f, path, group):
    """{ci, sigma, estimator, tau_int}_batch of the honest interval of /steady/<observable>
    `group`: its batch subgroup (steady_ci: independent), the group itself when its estimator is
    ensembles or blocking (steady_ci: batch), else None each (a file without them)."""
    where = f"{group}/batch" if f"{group}/batch" in f else group
    with reading(path, f"the attributes of /{where}"):
        attrs = dict(f[where].attrs)
    estimator = text(attrs["estimator"]) if "estimator" in attrs else None
    if estimator not in ("ensembles", "blocking"):
        return {f"{key}_batch": None for key in ("ci", "sigma", "estimator", "tau_int")}
    # NaN where fewer than two ensembles leave nothing to measure (docs/output.md)
    return {"ci_batch": float(read_dataset(f, f"{where}/ci", path)),
            "sigma_batch": float(read_dataset(f, f"{where}/sigma", path)), "estimator_batch": estimator,
            "tau_int_batch": float(attrs["tau_int"]) if "tau_int" in attrs else None}


def read_steady(path):
    """The steady-state averages of a run (RW05 §4.2) and its event counts: dict. mean, ci: the
    file's /steady average of the uncentred temperature and its half-width (with steady_ci:
    independent, the papers' one); ci_batch, sigma_batch, estimator_batch, tau_int_batch: the
    honest interval of the same average and the integrated autocorrelation time in
    observations it measured (None for a file without it)."""
    with open_run(path) as f:
        config = read_config(f, path)
        if "steady" not in f:
            raise ValueError(f"{path}: no /steady group (run without dsmc.steady_from)")
        out = {
            **_batch_interval(f, path, f"steady/{TEMPERATURE}"),
            "config": config,
            "n": int(config["dsmc"]["particles"]),
            "N": int(f.attrs["ensembles"]),
            "time": read_finite(f, "time", path),
            "series": read_finite(f, f"{TEMPERATURE}/mean", path),
            **{key: float(read_finite(f, f"steady/{TEMPERATURE}/{key}", path)) for key in ("mean", "ci")},
            "mean_centred": float(read_finite(f, f"steady/{TEMPERATURE_CENTRED}/mean", path)),
            **{f"events_{key}": read_dataset(f, f"events/{key}", path).astype(float)
               for key in ("collisions", "fictitious", "kicks")},
            **run_attrs(f),
        }
        return out
