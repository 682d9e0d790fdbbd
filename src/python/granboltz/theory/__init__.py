"""granboltz.theory: closed forms and exact results, pure (numpy, scipy, mpmath; no files, no verdicts).

Modules:
    closed_forms       temperature laws (GRW05 eqs. 16-17), the schemes' exact means (RW05), the
                       estimator's bias, the TV06 §3.1 formulas; its names are also this package's
    sonine             Sonine a2, a3 and the steady temperature of the heated gas
    maxwell_hierarchy  the exact moment hierarchy of Maxwell molecules
    tail_theory        the high-energy tail amplitude from the moments
    dimension          the checks of the dimension d and the collision geometry
    hcs                Haff's law and the a2 references of the homogeneous cooling state
    hcs_tail           the exponential tail of the HCS of hard spheres: its amplitude, the cooling rates
    viscoelastic       the viscoelastic restitution law and its free cooling, T ~ t^(-5/3)
    disks              the Sonine references and the white-noise temperature of hard disks (d = 2)
    mixtures           Garzó-Dufty partial cooling rates, the temperature ratios, Martin-Piasecki
    rough              rough particles: theta = T_rot/T_tr of the HCS and of white noise

LAMBDA_P, the confidence half-width factor of the whole project, is defined here (and only here);
the other names of closed_forms are loaded on first use, so that importing this package is light.
"""

LAMBDA_P = 3.2  # confidence half-width factor of GRW05 §5.1 (p = 0.999); the simulator's ci

_SUBMODULES = {"closed_forms", "sonine", "maxwell_hierarchy", "tail_theory", "dimension", "hcs", "hcs_tail",
               "viscoelastic", "disks", "mixtures", "rough"}


def __getattr__(name):
    # granboltz.theory.<name> was one module before the theory became a package: its names
    # (closed_forms, which re-exports sonine's) stay reachable here, imported on first use (scipy).
    if name.startswith("__") or name in _SUBMODULES:
        # not yet imported submodules: AttributeError lets `from . import sonine` import them
        raise AttributeError(name)
    import importlib

    module = importlib.import_module(".closed_forms", __name__)
    try:
        return getattr(module, name)
    except AttributeError:
        raise AttributeError(f"module 'granboltz.theory' has no attribute {name!r}") from None
