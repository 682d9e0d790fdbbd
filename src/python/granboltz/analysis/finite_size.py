"""The n -> infinity limit of a steady observable: fit T(n) = T_inf + c/n over runs at several
particle numbers n, by weighted least squares with the runs' own standard errors.

Why 1/n: an n-particle system's collision rate carries the factor (n - 1)/n (each particle meets
n - 1 others) and the centred estimator loses one degree of freedom of n, so the leading
finite-size term of the moment equations, and of the steady temperature, is of order 1/n (for
Maxwell molecules E T_n = (1 - 1/n) T_inf exactly: c = -T_inf).  Terms of order 1/n^2 are left
out: keep n large enough (tens of particles and up) that they are below the errors, and read
chi2/dof as the check of that (about 1 if the model and the errors hold).

The errors are taken as known (sigma = ci / lambda_p, the simulator's half-width over its
lambda_p = 3.2 standard errors, GRW05 §5.1): the covariance is (X^T W X)^-1, not rescaled by
chi2/dof.  A run's steady ci treats its (ensemble, time) samples as independent, so observation
times closer than the relaxation time make sigma, and the interval, too small.
"""

import math
from dataclasses import dataclass

import numpy as np

from ..theory import LAMBDA_P


@dataclass(frozen=True)
class FiniteSizeFit:
    """Result of fit_finite_size: T_inf and c with standard errors, their covariance [[var T_inf,
    cov], [cov, var c]], chi2 and its degrees of freedom, and z, the half-width factor of the
    intervals (default lambda_p = 3.2: the project's 99.86 % two-sided level for normal errors)."""

    T_inf: float
    c: float
    se_T_inf: float
    se_c: float
    cov: np.ndarray
    chi2: float
    dof: int
    z: float
    n: np.ndarray

    @property
    def chi2_dof(self):
        """chi2 / dof (NaN with two points: the line goes through them)."""
        return self.chi2 / self.dof if self.dof > 0 else math.nan

    @property
    def level(self):
        """Two-sided coverage of the intervals for normal errors: erf(z / sqrt 2)."""
        return math.erf(self.z / math.sqrt(2))

    @property
    def T_inf_interval(self):
        """(low, high) = T_inf -/+ z se_T_inf."""
        return self.T_inf - self.z * self.se_T_inf, self.T_inf + self.z * self.se_T_inf

    @property
    def c_interval(self):
        """(low, high) = c -/+ z se_c."""
        return self.c - self.z * self.se_c, self.c + self.z * self.se_c

    def predict(self, n):
        """T_inf + c/n at particle numbers n."""
        return self.T_inf + self.c / np.asarray(n, dtype=float)

    def __str__(self):
        from ..output.summary import format_pm

        return (f"T_inf = {format_pm(self.T_inf, self.z * self.se_T_inf)}, c = {format_pm(self.c, self.z * self.se_c)}"
                f" (± {self.z:g} se, {len(self.n)} sizes, chi2/dof = {self.chi2_dof:.2f})")


def fit_finite_size(n, T=None, sigma=None, z=LAMBDA_P, observable="temperature"):
    """Weighted least-squares fit of T(n) = T_inf + c/n (module docstring: the assumptions).

    Either arrays n, T, sigma (standard errors, not half-widths), or n a list of read_run objects
    of DSMC runs with dsmc.steady_from that differ only in particles and seed: T their steady
    `observable`, sigma its ci / lambda_p.  Returns a FiniteSizeFit; its intervals are -/+ z se."""
    if T is None:
        n, T, sigma = _from_runs(list(n), observable)
    n, T, sigma = (np.asarray(x, dtype=float).ravel() for x in (n, T, sigma))
    if not (n.size == T.size == sigma.size) or n.size < 2:
        raise ValueError(f"need n, T, sigma of one length >= 2, got {n.size}, {T.size}, {sigma.size}")
    if np.any(sigma <= 0) or not np.all(np.isfinite(sigma)) or np.unique(n).size < 2:
        raise ValueError("sigma must be positive and finite, and n take at least two values")
    X = np.column_stack([np.ones_like(n), 1.0 / n]) / sigma[:, None]
    y = T / sigma
    cov = np.linalg.inv(X.T @ X)
    coef = cov @ (X.T @ y)
    chi2 = float(np.sum((y - X @ coef) ** 2))
    return FiniteSizeFit(T_inf=float(coef[0]), c=float(coef[1]), se_T_inf=float(math.sqrt(cov[0, 0])),
                         se_c=float(math.sqrt(cov[1, 1])), cov=cov, chi2=chi2, dof=n.size - 2, z=float(z), n=n)


def _from_runs(runs, observable):
    """(n, T, sigma) of steady DSMC runs, refusing a shard, a run without steady averages, or runs
    whose physics differ in more than particles and seed."""
    import h5py

    def physics(run):
        d = {k: v for k, v in run.config["dsmc"].items() if k != "particles"}
        return repr(sorted(d.items()))

    rows = []
    for run in runs:
        if run.model != "dsmc" or not run.complete or observable not in run.steady:
            raise ValueError(f"{run.path}: need a whole DSMC run with steady {observable} (dsmc.steady_from)")
        if physics(run) != physics(runs[0]):
            raise ValueError(f"{run.path}: its dsmc section differs from {runs[0].path}'s in more than particles")
        with h5py.File(run.path, "r") as f:  # the file's own lambda_p (3.2 in every output so far)
            lambda_p = float(f.attrs["confidence_lambda_p"])
        s = run.steady[observable]
        rows.append((run.config["dsmc"]["particles"], float(s.mean), float(s.ci) / lambda_p))
    return tuple(zip(*rows))
