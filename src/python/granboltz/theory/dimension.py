"""The dimension d, and in d = 2 the collision geometry, that a theory function is stated for.

Every theory function of the package takes d (3 unless given: the papers' gas) and, where the law
of the impact normal matters, geometry (docs/config.md, Dimension and collision geometry:
"impact", the hard-sphere/hard-disk law, or "uniform", GRW05's uniform direction; in d = 3 the two
are one law, in d = 2 two different models; None: the simulator's default, "impact" in d = 2).
Where the package has no theory for a (d, geometry) the function raises ValueError with one line
naming itself, the value and what it has.  A caller that knows the run's d passes it
(run_geometry gives both).  TV06's formulas (granboltz.theory, its intruder and needle) belong to
its own one- and two-dimensional models and take no d.
"""

import numbers

GEOMETRIES = ("impact", "uniform")


def _short(value):
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


def check_dimension(d, supported, what):
    """d as an int if it is one of `supported` (e.g. (2, 3)), else ValueError naming `what`."""
    if isinstance(d, bool) or not isinstance(d, numbers.Integral) or int(d) not in supported:
        have = " or ".join(f"d = {s}" for s in supported)
        raise ValueError(f"{what}: no theory for d = {_short(d)} (only {have})")
    return int(d)


def check_geometry(d, geometry, what, supported=("impact",)):
    """The geometry of a d-dimensional theory stated, in d = 2, for the laws `supported`: None is
    the simulator's default ("impact" in d = 2; in d = 3 "uniform" is the same law); ValueError
    naming `what` for any other."""
    geometry = "impact" if geometry is None else geometry
    if geometry not in GEOMETRIES:
        raise ValueError(f"{what}: geometry = {_short(geometry)}, not 'impact' or 'uniform'")
    if d == 3 or geometry in supported:
        return geometry
    raise ValueError(f"{what}: no theory for geometry {geometry!r} in d = {d} (only {' or '.join(supported)})")


def dsmc_geometry(section):
    """(d, geometry) of a config's dsmc section: dsmc.dimension (3 unless set) and dsmc.geometry
    (its default by d: impact in d = 2, uniform in d = 3)."""
    d = int(section.get("dimension", 3))
    return d, section.get("geometry", "impact" if d == 2 else "uniform")


def run_geometry(run):
    """(d, geometry) of a DSMC run (read_run object): dsmc_geometry of its config."""
    return dsmc_geometry(run.config.get("dsmc", {}))


def initial_temperature(dsmc):
    """T0 of a run config's dsmc section: dsmc.initial.temperature, or the trace / d of a
    temperature tensor (an anisotropic Maxwellian; its temperature is that trace / d)."""
    T = dsmc.get("initial", {}).get("temperature", 1.0)
    if isinstance(T, (list, tuple)):
        return sum(float(T[a][a]) for a in range(len(T))) / len(T)
    return T


def check_maxwellian_start(dsmc, what):
    """ValueError naming `what` unless the run starts from the isotropic Maxwellian (theories of
    every speed moment from t = 0 need it; the temperature alone does not)."""
    init = dsmc.get("initial", {})
    if isinstance(init.get("temperature", 1.0), (list, tuple)):
        raise ValueError(f"{what}: needs an isotropic Maxwellian start, not dsmc.initial.temperature "
                         f"= {_short(init['temperature'])}")
