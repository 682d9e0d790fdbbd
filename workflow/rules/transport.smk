"""Transport and rheology: Navier–Stokes coefficients of the homogeneous cooling state (Gaussian
thermostat) and the rheology of uniform shear flow, Maxwell molecules (lambda = 0, geometry
uniform: exact) and hard spheres/disks (lambda = 1: first Sonine and Grad approximations).

Raw runs:  results/transport/<case>/<model>/d<d>/alpha=<alpha>/N=<ensembles>/n=<particles>/run.h5
           <case> = relax_eta (a prepared shear stress, initial.temperature a matrix),
           relax_kappa (a prepared heat flux, initial.heat_flux), usf_gaussian_a<a*> (steady shear
           flow under the Gaussian thermostat at the reduced rate a* = a/nu or a/nu0(T0)),
           usf_none_a<a> (steady shear flow of hard spheres without thermostat at the rate a),
           gk (the HCS under the Gaussian thermostat with the time correlations of the stress,
           a tagged velocity and the heat flux: Green–Kubo);
           <model> = maxwell or hard_spheres (d3 spheres, d2 disks with the impact law)
Items:     the table transport_coefficients (granboltz.transport_table) and the table
           shear_rheology (granboltz.rheology), each with a figure, in the report section
           "Transport and rheology"; the verdicts are computed in granboltz.transport_table.
"""

TRANSPORT = config["transport"]
TRANSPORT_SECTION = "Transport and rheology"
TR_RELAX, TR_USF, TR_GK = TRANSPORT["relaxation"], TRANSPORT["usf"], TRANSPORT["green_kubo"]
TRANSPORT_CASES = "relax_eta|relax_kappa|usf_gaussian_a[0-9.]+|usf_none_a[0-9.]+|gk"


def check_transport(t):
    """Cross-key checks of config transport the schema cannot express; ValueError naming the key."""
    for name, item in (("relaxation", t["relaxation"]), ("usf", t["usf"]), ("green_kubo", t["green_kubo"])):
        if not _whole(item["t_end"], item["observe_every"]):
            raise ValueError(f"transport.{name}: t_end must be a whole multiple of observe_every")
    lo, hi = t["relaxation"]["window"]
    if not 0 <= lo < hi <= t["relaxation"]["t_end"]:
        raise ValueError(f"transport.relaxation.window = {[lo, hi]}: need 0 <= t1 < t2 <= t_end")
    if not t["usf"]["steady_from"] < t["usf"]["t_end"]:
        raise ValueError("transport.usf: need steady_from < t_end")
    if not t["green_kubo"]["from"] < t["green_kubo"]["t_end"]:
        raise ValueError("transport.green_kubo: need from < t_end")
    for key in ("maxwell_reduced_rates", "reduced_rates"):
        if len(t["usf"][key]) < 2:
            raise ValueError(f"transport.usf.{key}: the extrapolation to a -> 0 needs at least 2 rates")


check_transport(TRANSPORT)


def transport_C(d):
    """C per unit angle: 1/|S^{d-1}| (Maxwell molecules collide once per unit time) times transport.C_factor."""
    return TRANSPORT["C_factor"] / (4 * math.pi if int(d) == 3 else 2 * math.pi)


def transport_nu(model, d):
    """The collision-rate unit of the reduced shear rate at T0: nu (lambda = 0) or nu0 (hard spheres)."""
    from granboltz.theory.shear import hard_sphere_nu0

    C = transport_C(d)
    if model == "maxwell":
        return (4 * math.pi if int(d) == 3 else 2 * math.pi) * TRANSPORT["gamma"] * C
    return hard_sphere_nu0(TRANSPORT["temperature0"], TRANSPORT["gamma"], C, d=int(d))


def transport_runs(case, model, d, alphas, item):
    return expand("results/transport/{case}/{model}/d{d}/alpha={alpha}/N={N}/n={n}/run.h5", case=case, model=model,
                  d=d, alpha=alphas, N=item["ensembles"], n=item["particles"])


def transport_run_config(wildcards):
    """Run config of results/transport/{case}/{model}/d{d}/alpha={alpha}/...: Gaussian thermostat
    (or none for usf_none_*), lambda 0 with geometry uniform or lambda 1 (d = 2: impact law)."""
    d, T0 = int(wildcards.d), float(TRANSPORT["temperature0"])
    lam = 0 if wildcards.model == "maxwell" else 1
    physics = {"alpha": float(wildcards.alpha), "beta": 0.0, "gamma": TRANSPORT["gamma"],
               "kernel": {"lambda": lam, "C": transport_C(d)}, "temperature0": T0}
    extra = {"dimension": d}
    if lam == 0 or d == 2:  # the exact map of lambda = 0; the hard-disk impact law (spheres: the default)
        extra["geometry"] = "uniform" if lam == 0 else "impact"
    if wildcards.case == "gk":
        item = TR_GK
        extra["thermostat"] = "gaussian"
        if lam == 1:
            extra["majorant"] = "pairwise"
        each = {"from": item["from"], "levels": item["levels"]}
        extra["correlations"] = {"velocity": dict(each), "stress": dict(each), "heat_flux": dict(each)}
    elif wildcards.case.startswith("relax"):
        item = TR_RELAX
        extra["thermostat"] = "gaussian"
        if lam == 1:
            extra["majorant"] = "pairwise"  # exact without kicks (as the HCS runs of beyond.smk)
        if wildcards.case == "relax_eta":
            tensor = [[T0 if i == j else 0.0 for j in range(d)] for i in range(d)]
            tensor[0][1] = tensor[1][0] = float(item["shear_stress"]) * T0
            extra["initial"] = {"temperature": tensor}
        else:
            extra["initial"] = {"temperature": T0, "heat_flux": [float(item["heat_flux"])] + [0.0] * (d - 1)}
    else:
        item = TR_USF
        rate = float(wildcards.case.rsplit("_a", 1)[1])
        if wildcards.case.startswith("usf_gaussian"):
            extra["thermostat"] = "gaussian"
            rate *= transport_nu(wildcards.model, d)
            if lam == 1:  # shear under the Gaussian thermostat: hard spheres need a splitting scheme
                extra.update(scheme="strang", steps=int(round(item["steps_per_unit"] * item["t_end"])))
        else:
            extra["thermostat"] = "none"
        extra.update(shear={"rate": rate}, steady_from=item["steady_from"], steady_ci="batch")
    label = f"transport/{wildcards.case}/{wildcards.model}/d{d}/alpha={wildcards.alpha}/n={wildcards.n}"
    return dsmc_run_config(label, physics, wildcards.N, wildcards.n, item["t_end"], item["observe_every"], **extra)


localrules:
    transport_run_config,


use rule run_config as transport_run_config with:
    output:
        yaml="results/transport/{case}/{model}/d{d}/alpha={alpha}/N={N}/n={n}/run.yaml",
    log:
        "logs/transport/{case}/{model}/d{d}/alpha={alpha}/N={N}/n={n}/run_config.log",
    wildcard_constraints:
        case=TRANSPORT_CASES,
        model="maxwell|hard_spheres",
        d="2|3",
        alpha="[0-9.]+",
    params:
        run=transport_run_config,


use rule run as transport_run with:
    input:
        config=rules.transport_run_config.output.yaml,
        granboltz=config["granboltz"],
    output:
        h5="results/transport/{case}/{model}/d{d}/alpha={alpha}/N={N}/n={n}/run.h5",
    log:
        "logs/transport/{case}/{model}/d{d}/alpha={alpha}/N={N}/n={n}/run.log",
    benchmark:
        "benchmarks/transport/{case}/{model}/d{d}/alpha={alpha}/N={N}/n={n}/run.tsv"
    wildcard_constraints:
        case=TRANSPORT_CASES,
        model="maxwell|hard_spheres",
        d="2|3",
        alpha="[0-9.]+",


TR_RELAX_RUNS = (
    transport_runs(["relax_eta", "relax_kappa"], "maxwell", 3, TR_RELAX["maxwell_alphas"], TR_RELAX)
    + transport_runs(["relax_eta", "relax_kappa"], "hard_spheres", 3, TR_RELAX["alphas"], TR_RELAX)
    + transport_runs("relax_eta", "hard_spheres", 2, TR_RELAX["disk_alphas"], TR_RELAX)
)
TR_USF_GAUSSIAN = transport_runs([f"usf_gaussian_a{a}" for a in TR_USF["maxwell_reduced_rates"]], "maxwell", 3,
                                 TR_USF["maxwell_alphas"], TR_USF) + transport_runs(
    [f"usf_gaussian_a{a}" for a in TR_USF["reduced_rates"]], "hard_spheres", 3, TR_USF["alphas"], TR_USF)
TR_GK_RUNS = (transport_runs("gk", "maxwell", 3, TR_GK["maxwell_alphas"], TR_GK)
              + transport_runs("gk", "maxwell", 2, TR_GK["maxwell_disk_alphas"], TR_GK)
              + transport_runs("gk", "hard_spheres", 3, TR_GK["alphas"], TR_GK)
              + transport_runs("gk", "hard_spheres", 2, TR_GK["disk_alphas"], TR_GK))
TR_USF_FREE = transport_runs([f"usf_none_a{TR_USF['free_rate']}"], "hard_spheres", 3, TR_USF["free_alphas"], TR_USF)


rule transport_coefficients:
    input:
        relaxation=TR_RELAX_RUNS,
        usf=TR_USF_GAUSSIAN,
        green_kubo=TR_GK_RUNS,
    output:
        csv=report("results/tables/transport_coefficients.csv", caption=item_caption("transport_coefficients"), category=TRANSPORT_SECTION),
        png=report("figures/transport_coefficients.png", caption=item_caption("transport_coefficients"), category=TRANSPORT_SECTION),
        pdf="figures/transport_coefficients.pdf",
        summary="results/figures/transport_coefficients.json",
    log:
        "logs/figures/transport_coefficients.log",
    benchmark:
        "benchmarks/figures/transport_coefficients.tsv"
    params:
        window=TR_RELAX["window"],
    script:
        "../scripts/transport_coefficients.py"


rule shear_rheology:
    input:
        runs=TR_USF_GAUSSIAN + TR_USF_FREE,
    output:
        csv=report("results/tables/shear_rheology.csv", caption=item_caption("shear_rheology"), category=TRANSPORT_SECTION),
        png=report("figures/shear_rheology.png", caption=item_caption("shear_rheology"), category=TRANSPORT_SECTION),
        pdf="figures/shear_rheology.pdf",
        summary="results/figures/shear_rheology.json",
    log:
        "logs/figures/shear_rheology.log",
    benchmark:
        "benchmarks/figures/shear_rheology.tsv"
    script:
        "../scripts/shear_rheology.py"


for _rule, _name, _what, _runs in (
    (rules.transport_coefficients, "Transport coefficients",
     "η*, κ*, μ*, D* of hard spheres (d = 3; η*, D* of disks, d = 2) against α from relaxation, from shear "
     "flow at a → 0 and from Green–Kubo integrals of the HCS's time correlations, beside the standard and "
     "modified first Sonine values; λ = 0 rows against the exact Chapman–Enskog values",
     TR_RELAX_RUNS + TR_USF_GAUSSIAN + TR_GK_RUNS),
    (rules.shear_rheology, "Shear rheology",
     "P_ij/p of uniform shear flow: λ = 0 under the Gaussian thermostat against the exact rheology, hard spheres "
     "(thermostatted and free) against the nonlinear Grad closure", TR_USF_GAUSSIAN + TR_USF_FREE)):
    report_item(TRANSPORT_SECTION, _name, _rule, "figure", _rule.output.png, _what, runs=_runs,
                run_rule=rules.transport_run, summary=_rule.output.summary)
    report_item(TRANSPORT_SECTION, _name + " (table)", _rule, "table", _rule.output.csv, _what,
                compare=_rule.rule.name)
