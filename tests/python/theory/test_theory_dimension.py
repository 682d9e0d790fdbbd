"""Every theory function of the package takes the dimension d (and, where the impact law matters,
the geometry) and raises ValueError with one line where it has no theory for that d
(granboltz.theory.dimension).  The scan below fails for a new public function of a theory module that
neither takes d nor is listed as d-free with its reason."""

import importlib
import inspect
import types

import pytest

THEORY_MODULES = ["sonine", "theory.closed_forms", "maxwell_hierarchy", "viscoelastic", "tail_theory", "hcs_tail", "beyond",
                  "disks", "mixtures", "rough", "moment_checks", "shear", "transport", "theory.hcs", "theory.viscoelastic",
                  "theory.hcs_tail", "theory.disks", "theory.mixtures", "theory.rough"]

# d-free, and why: data (rows, verdicts, fits of a run's numbers), utilities, or another model's formula
D_FREE = {
    "theory.closed_forms": {"dsmc_physics", "run_analytic_temperature", "expected_error",  # read d from the run's config
               # TV06's intruder (1-D) and needle (2-D): their own models, not dsmc.dimension
               "gaussian_pdf", "powerlaw_pdf", "gaussian_fluxes", "fluxes_by_quadrature", "colliding_density",
               "colliding_mass", "gaussian_temperature_ratio", "exact_temperature_ratio",
               "t_coverage"},  # statistics
    "maxwell_hierarchy": {"rational", "evaluate"},  # number utilities
    "theory.viscoelastic": {"restitution"},  # the contact law eps(g_n): one dimension
    "viscoelastic": {"run_delta", "log_spaced", "viscoelastic_rows", "late_slope", "slope_verdict", "elastic_verdict",
                     "viscoelastic_verdict", "short_verdict"},
    "tail_theory": {"example_tail",  # GRW05's examples, d = 3
                    "local_eq38_slope", "eq38_slope", "offset_for_slope"},  # what a fit sees of a given profile
    "theory.hcs_tail": {"thermal_speed"},  # v0 = sqrt(2T/m), a definition
    "hcs_tail": {"exponential_fit", "hcs_tail_row_verdict"},
    "beyond": {"run_alpha", "haff_rows", "a2_rows", "steady_histogram", "haff_verdict", "a2_agrees", "a2_verdict",
               "a2_item_verdict", "tail_verdict", "haff_item_verdict", "tail_item_verdict"},  # rows take d from each run's config
    "disks": {"disk_a2_rows", "disk_judge", "disk_place", "disk_a2_verdict", "disk_item_verdict", "disk_summary_verdict"},
    "mixtures": {"mixture_correlation", "mixture_rows", "mixture_verdict"},
    "rough": {"rough_rows", "rough_verdict"},
    "transport": {"usf_viscosity", "correlation_integral", "read_correlation", "green_kubo"},  # a fit of runs; an integral of given data
    "moment_checks": {"hierarchy_physics", "read_speed_moments", "moment_verdict", "rw05_moment_rows",
                      "crit_estimator_bias", "crit_verdict", "crit_of_means"},  # from a run or its config (d = 3 checked there)
}

A3_RUN = types.SimpleNamespace(steady={"a3": types.SimpleNamespace(mean=0.0, ci=0.1)})
# function: (arguments valid at d = 3, the d with a theory)
TWO, THREE = (2, 3), (3,)
CASES = {
    "sonine.first_sonine_a2": ((0.8, "gaussian", 1), TWO), "sonine.second_sonine": ((0.8, "gaussian"), TWO),
    "sonine.maxwell_a2": ((0.8,), THREE), "sonine.maxwell_a3": ((0.8,), THREE),
    "sonine.hcs_moment_threshold": ((4,), THREE), "sonine.sonine_from_moments": ((3.0, 15.0), TWO),
    "sonine.cooling_rate": ((1.0, 0.8, 1.0, 0.1, 1), TWO), "sonine.steady_temperature": ((0.8, 1.0, 1.0, 0.1, 1), TWO),
    "sonine.maxwell_steady_temperature": ((0.8, 1.0, 1.0, 0.1), TWO),
    "sonine.hard_sphere_steady_temperature": ((0.8, 1.0, 1.0, 0.1), TWO),
    "theory.closed_forms.maxwell_rate": ((0.5, 1.0, 0.1), TWO), "theory.closed_forms.analytic_temperature": (([0.0, 1.0], 1.0, 0.5, 1.0, 1.0, 0.1), TWO),
    "theory.closed_forms.scheme_temperature": (("euler", [0.5, 1.0], 0.5, 1.0, 0.5, 1.0, 1.0, 0.1), TWO),
    "theory.closed_forms.scheme_steady_temperature": (("strang", 0.5, 0.5, 1.0, 1.0, 0.1), TWO),
    "theory.closed_forms.uncentred_expectation": ((1.0, 1.0, 1.0, 0.5, 100), TWO),
    "maxwell_hierarchy.collision_rate": ((1, "1/4"), THREE), "maxwell_hierarchy.collision_coefficients": ((2, "1/2"), THREE),
    "maxwell_hierarchy.steady_moments": ((2, "1/2", 1, 1), THREE), "maxwell_hierarchy.maxwellian_moments": ((2, 1), THREE),
    "maxwell_hierarchy.time_dependent_moments": ((2, "1/2", 1, 1), THREE), "maxwell_hierarchy.sonine_a2": ((3, 16), THREE),
    "maxwell_hierarchy.steady_a2_formula": (("1/2",), THREE), "maxwell_hierarchy.crit": ((3.0, 15.5), THREE),
    "maxwell_hierarchy.crit_exact": (([0.5], "1/2", 1, 1), THREE), "maxwell_hierarchy.crit_steady": (("1/2", 1, 1), THREE),
    "maxwell_hierarchy.hcs_scaled_moments": ((2, "1/2"), THREE), "maxwell_hierarchy.hcs_a2": (("1/2",), THREE),
    "theory.viscoelastic.loss_fraction": ((1.0, 0.1), THREE), "theory.viscoelastic.cooling_rate_visco": ((1.0, 0.1, 1.0, 0.1), THREE),
    "theory.viscoelastic.tau0": ((0.1, 1.0, 1.0, 0.1), THREE),
    "theory.viscoelastic.asymptotic_temperature": (([1.0], 0.1, 1.0, 1.0, 0.1), THREE),
    "theory.viscoelastic.free_cooling_temperature": (([1.0], 0.1, 1.0, 1.0, 0.1), THREE),
    "theory.viscoelastic.local_slope": (([1.0], [0.5], 0.1, 1.0, 0.1), THREE),
    "theory.viscoelastic.late_slope_expansion": (([10.0], [0.5], 0.1, 1.0), THREE),
    "tail_theory.tail_exponent": ((1.0,), TWO), "tail_theory.fast_particle_rate": ((16.0, 0.25), TWO),
    "tail_theory.tail_amplitude": ((16.0, 30.0, 1.0), TWO), "tail_theory.amplitude_from_moments": (([1, 3, 15, 105],), TWO),
    "tail_theory.amplitude_and_chi_from_moments": (([1, 3, 15, 105, 945],), TWO),
    "tail_theory.importance_split": ((1.0, 30.0, 16.0, 0.08, 16.0, 4.0), TWO),
    "theory.hcs_tail.hcs_amplitude": ((1.0, 1.0, 0.08, 1.0), TWO), "theory.hcs_tail.maxwellian_cooling_rate": ((0.8, 1.0, 0.08, 1.0), TWO),
    "theory.hcs_tail.sonine_cooling_rate": ((0.8, 1.0, 0.08, 1.0), TWO),
    "hcs_tail.hcs_tail_summary": (None, TWO),  # data with theory: d passed to hcs_amplitude (checked through it)
    "theory.hcs.vne_hcs_a2": ((0.8,), TWO), "theory.hcs.vne_heated_a2": ((0.8,), TWO),
    "theory.hcs.theory_a2": (("gaussian", 1, 0.8), TWO), "theory.hcs.haff_temperature": (([1.0], 1.0, 0.8, 1.0, 0.08, 1), TWO),
    "beyond.a3_columns": ((A3_RUN, "gaussian", 1, 0.8), TWO),
    "theory.disks.disk_references": (("gaussian", 0.8), (2,)), "theory.disks.disk_steady_temperature": ((0.8, 1.0, 1.0, 0.16), (2,)),
    "theory.mixtures.partial_cooling_rates": (([1.0, 1.0], [2.0, 1.0], [0.5, 0.5], 0.8), TWO),
    "theory.mixtures.hcs_temperature_ratios": (([2.0, 1.0], [0.5, 0.5], 0.8), TWO),
    "theory.mixtures.white_noise_temperature_ratios": (([2.0, 1.0], [0.5, 0.5], 0.8), TWO),
    "theory.mixtures.temperature_ratio": (("gaussian", 2.0, 0.8), TWO), "theory.mixtures.martin_piasecki": ((0.5, 1.0), (1, 2, 3)),
    "theory.rough.coefficients": ((0.8, 0.5), TWO), "theory.rough.temperature_rates": ((1.0, 0.5, 0.8, 0.5), TWO),
    "theory.rough.hcs_theta": ((0.8, 0.5), TWO), "theory.rough.white_noise_theta": ((0.5,), TWO), "theory.rough.theta": (("gaussian", 0.8, 0.5), TWO),
    "moment_checks.moment_rows": (([3.0], [0.1], "1/2", 1, 1, 1, 0.5), THREE),
    "moment_checks.amplitude_rows": (("1/2", 1, 1, 6), THREE),
    "shear.maxwell_second_moment_rate": ((1.0, 0.5, 1.0, 0.3), TWO),
    "shear.maxwell_second_moments": ((1.0, 0.5, 1.0, 0.08, 0.3), TWO),
    "shear.maxwell_steady_shear_rate": ((0.5, 1.0, 0.08), TWO), "shear.maxwell_usf_ratios": ((0.5,), TWO),
    "shear.maxwell_gaussian_usf_ratios": ((0.5, 1.0, 1.0, 0.08), TWO),
    "shear.hard_sphere_nu0": ((1.0, 1.0, 0.08), TWO), "shear.hard_sphere_usf_grad": ((0.5, 1.0, 1.0, 0.08), THREE),
    "shear.hard_sphere_usf_grad_gaussian": ((0.5, 0.3), THREE),
    "transport.maxwell_rates": ((0.5,), TWO), "transport.maxwell_fourth_moment_rates": ((0.5,), TWO),
    "transport.maxwell_hcs_a2": ((0.5,), TWO), "transport.maxwell_coefficients": ((0.5,), TWO),
    "transport.maxwell_reduced": ((0.5,), TWO), "transport.hard_sphere_zeta_star": ((0.5, 0.01), TWO),
    "transport.hard_sphere_reduced": ((0.5,), TWO), "transport.hard_sphere_nu0_coefficients": ((0.5,), TWO),
    "shear.maxwell_drag_a2": ((0.5, 1.0), THREE), "shear.hard_sphere_drag_state": ((0.5, 1.0, 0.5, 1.0, 0.08), THREE),
}


def _function(name):
    module, _, attr = name.rpartition(".")
    return getattr(importlib.import_module(f"granboltz.{module}"), attr)


def test_every_theory_function_takes_d_or_is_listed_as_d_free():
    missing, stale = [], []
    for m in THEORY_MODULES:
        module = importlib.import_module(f"granboltz.{m}")
        for attr, obj in vars(module).items():
            f = getattr(obj, "__wrapped__", obj)  # lru_cache
            if attr.startswith("_") or not inspect.isfunction(f) or f.__module__ != module.__name__:
                continue
            takes_d = "d" in inspect.signature(f).parameters
            if takes_d and f"{m}.{attr}" not in CASES:
                missing.append(f"{m}.{attr} (takes d: add it to CASES)")
            if not takes_d and attr not in D_FREE.get(m, ()):
                missing.append(f"{m}.{attr} (no d, not listed as d-free)")
            if takes_d and attr in D_FREE.get(m, ()):
                stale.append(f"{m}.{attr}")
    assert not missing and not stale, (missing, stale)


@pytest.mark.parametrize("name", sorted(k for k, (args, _) in CASES.items() if args is not None))
def test_theory_functions_raise_where_they_have_no_theory(name):
    f = _function(name)
    args, supported = CASES[name]
    for d in supported:
        f(*args, d=d)  # a theory exists: it answers
    for d in {1, 2, 3, 4} - set(supported) | {2.5, True, "3"}:
        with pytest.raises(ValueError) as err:
            f(*args, d=d)
        text = str(err.value)
        assert "\n" not in text and "no theory for d" in text and len(text) < 160, (name, d, text)
    if "geometry" in inspect.signature(f).parameters and 2 in supported:
        with pytest.raises(ValueError, match="geometry"):
            f(*args, d=2, geometry="sideways")


def test_disk_impacts_and_the_uniform_law_are_different_theories():
    from granboltz import theory

    # the hard-disk results need the impact law; the exact Maxwell-molecule rate has both laws
    from granboltz.reproduction import rough
    from granboltz.theory import sonine
    for f, args in ((rough.hcs_theta, (0.8, 0.5)), (sonine.first_sonine_a2, (0.8, "gaussian", 1))):
        with pytest.raises(ValueError, match="no theory for geometry 'uniform' in d = 2"):
            f(*args, d=2, geometry="uniform")
    assert theory.maxwell_rate(0.5, 1.0, 1.0, d=2, geometry="uniform") == pytest.approx(0.75 * 3.14159265 / 2)
    assert theory.maxwell_rate(0.5, 1.0, 1.0, d=2) == pytest.approx(0.75 * 2 * 3.14159265 / 3)
    assert rough.hcs_theta(0.8, 0.5, d=3, geometry="uniform") == rough.hcs_theta(0.8, 0.5)  # one law in d = 3
