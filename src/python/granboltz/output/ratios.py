"""The ratios the simulator stores as observables of their own (docs/output.md, Mixtures and rough
spheres): theta = T_rot/T of rough particles (/theta) and T_a/T_b of every pair a < b of a
mixture's species in the order they are listed (/temperature_ratio/<a>_over_<b>), each with
mean, ci and bias per row and, with dsmc.steady_from, /steady/<group>/{mean,sigma,ci,bias}.

Their mean is the ratio of the ensemble means (of the steady averages under /steady); their
interval the delta method with the variances and the covariance of the two temperatures over the
ensembles (for /steady, of the ensembles' time averages, estimator "ensembles" whatever
dsmc.steady_ci says, Student-t with N - 1 degrees of freedom below 30), from exact cross sums at
/accumulators/<prefix>cross and <prefix>steady_cross. read_run gives them as run.theta,
run.steady["theta"], run.temperature_ratios["<a>_over_<b>"] and
run.steady["temperature_ratio/<a>_over_<b>"]. T_b/T_a is 1/(T_a/T_b): to first order its
relative interval is the same.
"""

from .intervals import IntervalSpec
from .layout import SUMS, F8, I8, Spec
from .species import species_entries


def ratio_groups(section):
    """[(group, accumulator prefix, condition)] of the ratios a config's output has (dsmc/run.cpp
    ratio_sets): theta with dsmc.roughness, then T_a/T_b for the species pairs a < b."""
    out = [("theta", "theta_", "dsmc.roughness")] if section.get("roughness") is not None else []
    names = [str(e.get("name")) for e in species_entries(section)]
    for i, a in enumerate(names):
        for j in range(i + 1, len(names)):
            out.append((f"temperature_ratio/{a}_over_{names[j]}", f"ratio_{i}_{j}_", "dsmc.species"))
    return out


def ratio_layout(reader, section, R, steady, out, acc):
    """Adds the ratios to a DSMC layout (layout.dsmc_layout): series specs to out["observables"],
    steady specs and intervals to out["steady"], out["intervals"], cross sums to acc.  Required
    where the file has the ratio's cross sums (every output of a simulator that stores them);
    files of older simulators have none, and read without them."""
    for group, prefix, condition in ratio_groups(section):
        if not reader.exists(f"accumulators/{prefix}cross"):
            continue
        why = reader.why(condition)
        out["observables"][group] = [Spec(f"{group}/{key}", F8, (R,), True, why) for key in ("mean", "ci", "bias")]
        acc.append(Spec(f"accumulators/{prefix}cross", I8, (R,) + SUMS, True, why))
        if steady:
            g, s_why = f"steady/{group}", reader.why(f"{condition} and dsmc.steady_from")
            out["steady"][g] = [Spec(f"{g}/{key}", F8, (), True, s_why) for key in ("mean", "ci", "bias")]
            out["intervals"][g] = IntervalSpec(g, (), True, ("ensembles",), s_why, keys=())
            acc.append(Spec(f"accumulators/{prefix}steady_cross", I8, (1,) + SUMS, True, s_why))
