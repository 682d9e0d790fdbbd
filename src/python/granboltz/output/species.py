"""The species of a DSMC mixture (config dsmc.species) as read_run reads them: run.species[name].

    sp = run.species["heavy"]
    sp.temperature.mean, .ci      # T_i = m_i <|v - V|^2>_i / d, V the mixture's centre-of-mass velocity
    sp.a2.mean, .ci, .bias        # its Sonine coefficients (moments >= 2; a3 with moments >= 3)
    sp.steady["temperature"]      # its steady average (dsmc.steady_from): mean, ci, sigma, ...
    sp.mass, sp.diameter, sp.fraction, sp.particles   # fraction = N_i/n, particles N_i
    sp.events["collisions"]       # per ensemble: the real collisions a particle of it took part in

The layout (docs/output.md, Mixtures): every observable of the one-species gas per species under
/species/<name>/ ([M+1, ...] mean, ci, variance), /species/<name>/a2 (and a3) with mean, ci,
bias, the group's attributes mass, diameter, fraction and particles, with dsmc.steady_from
/steady/species/<name>/<observable> (mean, ci, variance, sigma; estimator, tau_int and
effective_samples as /steady/<observable>) and /steady/species/<name>/a2, and
/events/species/<name>/collisions.  Every dataset is required exactly when the stored config has
dsmc.species; a file that lacks one, or has it with the wrong shape, dtype or non-finite values,
raises RunReadError naming it.
"""

from dataclasses import dataclass, field

import numpy as np

from .layout import DSMC_OBSERVABLES, F8, U8, Spec, observable_specs

SONINE = (("a2", 2), ("a3", 3))  # (name, moments needed)


def species_entries(section):
    """The list of dsmc.species mappings of a config section ([] for a one-species gas)."""
    entries = section.get("species")
    return list(entries) if isinstance(entries, (list, tuple)) else []


def largest_remainder(fractions, n):
    """Particle counts N_i of n particles split by fractions (largest remainder: floor(f_i n),
    then one more to the largest remainders, ties to the earlier species)."""
    f = np.asarray(fractions, float)
    exact = f / f.sum() * n
    counts = np.floor(exact).astype(int)
    order = sorted(range(f.size), key=lambda i: (-(exact[i] - counts[i]), i))
    for i in order[: n - counts.sum()]:
        counts[i] += 1
    return counts.tolist()


def species_layout(reader, section, time, n, P, steady):
    """{name: {"observables", "sonine", "steady", "steady_sonine": {group: [Spec]}, "events": [Spec],
    "config": the dsmc.species entry}} of a mixture output; {} without dsmc.species."""
    why = reader.why
    R = time.size
    moments = [(f"moment_{2 * p}", ()) for p in range(1, P + 1)]
    out = {}
    for entry in species_entries(section):
        name = str(entry.get("name"))
        g, sg = f"species/{name}", f"steady/species/{name}"
        w = why("dsmc.species")
        m_w = why("dsmc.species and dsmc.moments > 0")
        obs = {o: observable_specs(f"{g}/{o}", trail, (R,), w) for o, trail in DSMC_OBSERVABLES}
        obs.update({o: observable_specs(f"{g}/{o}", trail, (R,), m_w) for o, trail in moments})
        sonine = {a: [Spec(f"{g}/{a}/{k}", F8, (R,), True, why(f"dsmc.species and dsmc.moments >= {p}"))
                      for k in ("mean", "ci", "bias")] for a, p in SONINE if P >= p}
        st, st_sonine = {}, {}
        if steady:
            s_w = why("dsmc.species and dsmc.steady_from")
            st = {o: [Spec(f"{sg}/{o}/{k}", F8, tuple(trail), True, s_w) for k in ("mean", "ci", "variance", "sigma")]
                  for o, trail in list(DSMC_OBSERVABLES) + moments}
            if P >= 2:
                st_sonine["a2"] = [Spec(f"{sg}/a2/{k}", F8, (), True, why("dsmc.species, steady_from, moments >= 2"))
                                   for k in ("mean", "sigma", "ci", "bias")]
        events = [Spec(f"events/{g}/collisions", U8, (n,), True, w)]
        out[name] = {"observables": obs, "sonine": sonine, "steady": st, "steady_sonine": st_sonine,
                     "events": events, "config": entry}
    return out


@dataclass(frozen=True)
class Species:
    """One species of a mixture run: its observables (attributes too: sp.temperature), a2/a3 in
    observables (with bias), steady averages, per-ensemble events and its group's attributes."""

    name: str
    mass: float
    diameter: float
    fraction: float
    particles: int
    observables: dict
    steady: dict = field(default_factory=dict)
    events: dict = field(default_factory=dict)

    def __getattr__(self, name):
        observables = self.__dict__.get("observables", {})
        if name in observables:
            return observables[name]
        raise AttributeError(f"species {self.__dict__.get('name')!r} has no attribute or observable {name!r}")

    def __repr__(self):
        return (f"Species {self.name}: mass {self.mass:g}, diameter {self.diameter:g}, {self.particles} particles "
                f"(fraction {self.fraction:g}); observables {', '.join(self.observables)}")


def _steady_fields(reader, g, specs, estimators):
    """mean, ci, variance, sigma of a /steady/species group and its estimator's attributes."""
    fields = {spec.name.rpartition("/")[2]: reader.dataset(spec) for spec in specs}
    why = specs[0].why
    if estimators or reader.has_attribute(g, "estimator"):
        fields["estimator"] = reader.text(g, "estimator", why)
        for key in ("tau_int", "effective_samples"):
            if estimators or reader.has_attribute(g, key):
                fields[key] = reader.number(g, key, why, nan=True)
    return fields


def read_species(reader, layout, section, n_file, particles):
    """{name: Species} of a mixture output by its species layout (species_layout); checks the
    group attributes against the config: mass, diameter as configured, particles the largest
    remainder of fraction * n (summing to n), fraction = particles/n."""
    from .run import Observable  # the observable type of read_run

    if not layout:
        return {}
    counts = largest_remainder([float(e.get("fraction", 0)) for e in species_entries(section)], particles)
    estimators = "steady_ci" in section
    out = {}
    for (name, lay), want in zip(layout.items(), counts):
        g, entry, w = f"species/{name}", lay["config"], reader.why("dsmc.species")
        reader.group(g, w)
        mass, diameter = reader.number(g, "mass", w), reader.number(g, "diameter", w)
        fraction, count = reader.number(g, "fraction", w), reader.integer(g, "particles", w, minimum=0)
        for key, got in (("mass", mass), ("diameter", diameter)):
            if not np.isclose(got, float(entry.get(key, 1.0)), rtol=1e-12):
                reader.fail(f"attribute {key} of /{g}", f"is {got:g}, but the config says {entry.get(key)!r}")
        if count != want:
            reader.fail(f"attribute particles of /{g}", f"is {count}, not {want} (largest remainder of fraction n)")
        if not np.isclose(fraction, count / particles, rtol=1e-12):
            reader.fail(f"attribute fraction of /{g}", f"is {fraction:g}, not particles/n = {count / particles:g}")
        obs = {o: Observable(name=f"{g}/{o}", **{s.name.rpartition("/")[2]: reader.dataset(s) for s in specs})
               for o, specs in lay["observables"].items()}
        obs.update({a: Observable(name=f"{g}/{a}", **{s.name.rpartition("/")[2]: reader.dataset(s) for s in specs})
                    for a, specs in lay["sonine"].items()})
        st = {o: Observable(name=f"steady/{g}/{o}", **_steady_fields(reader, f"steady/{g}/{o}", specs, estimators))
              for o, specs in lay["steady"].items()}
        st.update({a: Observable(name=f"steady/{g}/{a}", **{s.name.rpartition("/")[2]: reader.dataset(s) for s in specs})
                   for a, specs in lay["steady_sonine"].items()})
        if lay["steady"] and reader.exists(f"steady/{g}/a3/mean"):  # read, and checked, where present
            st["a3"] = Observable(name=f"steady/{g}/a3", **{k: reader.dataset(Spec(f"steady/{g}/a3/{k}", F8, ()))
                                                            for k in ("mean", "ci")})
        events = {s.name.rpartition("/")[2]: reader.dataset(s) for s in lay["events"]}
        out[name] = Species(name=name, mass=mass, diameter=diameter, fraction=fraction, particles=count,
                            observables=obs, steady=st, events=events)
    if sum(counts) != particles:
        reader.fail("attribute particles of /species", f"sums to {sum(counts)}, not n = {particles}")
    return out
