"""Beyond the papers: free cooling (Haff's law), the homogeneous cooling state under
the Gaussian thermostat and the white-noise steady state, against theory (docs/config.md,
Thermostats); free cooling of viscoelastic spheres (docs/config.md, Restitution laws); hard
disks in d = 2 (docs/config.md, Dimension and collision geometry).

Raw runs:  results/beyond/<thermostat>/<kernel>/<restitution>/N=<ensembles>/n=<particles>/run.h5
           with <thermostat> = none (Haff), gaussian or white_noise, <kernel> = maxwell (lambda = 0),
           hard_spheres (lambda = 1) or hard_disks (lambda = 1, dsmc.dimension 2, geometry impact:
           steady runs only), mixture-m<m1/m2> (a binary mixture of hard spheres, dsmc.species:
           steady runs) or rough-beta<beta> (rough hard spheres, dsmc.roughness: steady runs),
           <restitution> = alpha=<alpha> (constant) or delta=<delta> (viscoelastic: free-cooling
           hard spheres only)
           SWPM runs of the HCS tail: results/beyond_swpm/gaussian/hard_spheres/alpha=<alpha>/N=<N>/n=<n>/run.h5
           (dsmc.weights: swpm with importance splitting, config beyond.hcs_tail_swpm)
Items:     Haff's law (table + figure), a2(alpha) of both thermostats (table + figure), the HCS tail
           (local exponent of constant weights, table beyond_hcs_tail_profile + figure; b and A of the
           exponential tail with weighted particles, table beyond_hcs_tail), viscoelastic free cooling (T ~ t^(-5/3); table +
           figure), a2 and a3 of hard disks (table + figure), T1/T2 of a binary mixture and theta =
           T_rot/T_tr of rough spheres (tables + figures), in the report section "Beyond the papers".
"""

BEYOND = config["beyond"]
BEYOND_PAPER = "Beyond the papers"
BEYOND_LAMBDA = {"maxwell": 0, "hard_spheres": 1, "hard_disks": 1}
BEYOND_KERNELS = "maxwell|hard_spheres|hard_disks|mixture-m[0-9.]+|rough-beta-?[0-9.]+"


def check_beyond(b):
    """Cross-key checks of config beyond that the schema cannot express; ValueError naming the key."""
    visco = b["viscoelastic"]
    for name, timing in [("haff.maxwell", b["haff"]["maxwell"]), ("haff.hard_spheres", b["haff"]["hard_spheres"]),
                         ("a2", b["a2"]), ("viscoelastic", visco), ("viscoelastic.elastic", visco["elastic"]),
                         ("disks_a2", b["disks_a2"]), ("mixture", b["mixture"]), ("rough", b["rough"])]:
        if not _whole(timing["t_end"], timing["observe_every"]):
            raise ValueError(f"beyond.{name}: t_end must be a whole multiple of observe_every")
    for name in ("a2", "disks_a2", "mixture", "rough"):
        if not b[name]["steady_from"] < b[name]["t_end"]:
            raise ValueError(f"beyond.{name}: need steady_from < t_end")
    if not set(b["a2"]["key_alphas"]) <= set(b["a2"]["alphas"]):
        raise ValueError("beyond.a2.key_alphas: must be among beyond.a2.alphas")
    if b["tail"]["alpha"] not in b["a2"]["alphas"]:
        raise ValueError(f"beyond.tail.alpha = {b['tail']['alpha']}: must be one of beyond.a2.alphas")
    if not visco["late_from"] < visco["t_end"]:
        raise ValueError("beyond.viscoelastic: need late_from < t_end")


check_beyond(BEYOND)


def beyond_runs(thermostat, kernels, values, N, n, law="alpha"):
    """The HDF5 outputs of one thermostat for every kernel and value of alpha (law "delta": of the
    viscoelastic delta); values a list or one number."""
    values = values if isinstance(values, (list, tuple)) else [values]
    return expand(rules.beyond_run.output.h5, thermostat=thermostat, kernel=kernels,
                  restitution=[f"{law}={v}" for v in values], N=N, n=n)


def beyond_run_config(wildcards):
    """Run config of results/beyond/{thermostat}/{kernel}/{restitution}/N={N}/n={n}: free cooling
    with the haff timing of the kernel (delta=: the viscoelastic timing, or its elastic one for
    delta 0); gaussian and white_noise steady runs with the a2 timing (the hard-sphere Gaussian
    runs also keep the histogram of the tail); hard disks: steady runs in d = 2 with the disks_a2
    timing, C and beta (beyond_disk_config)."""
    if wildcards.kernel == "hard_disks":
        return beyond_disk_config(wildcards)
    if wildcards.kernel.startswith(("mixture-", "rough-")):
        return beyond_mixed_config(wildcards)
    law, value = wildcards.restitution.split("=")
    physics = {"beta": 0.0, "gamma": BEYOND["gamma"],
               "kernel": {"lambda": BEYOND_LAMBDA[wildcards.kernel], "C": BEYOND["C"]},
               "temperature0": BEYOND["temperature0"]}
    if law == "alpha":
        physics["alpha"] = float(value)
    elif wildcards.thermostat == "none" and wildcards.kernel == "hard_spheres":
        physics["restitution"] = {"law": "viscoelastic", "delta": float(value)}
    else:
        raise ValueError(f"{wildcards.restitution}: the viscoelastic runs are free-cooling hard spheres")
    extra = {"thermostat": wildcards.thermostat}
    if wildcards.thermostat != "white_noise" and wildcards.kernel == "hard_spheres":
        extra["majorant"] = "pairwise"  # exact without kicks; the global bound would reject most pairs as T falls
    if law == "delta":
        visco = BEYOND["viscoelastic"]
        timing = visco if float(value) > 0 else visco["elastic"]
    elif wildcards.thermostat == "none":
        timing = BEYOND["haff"][wildcards.kernel]
    else:
        timing = BEYOND["a2"]
        extra["steady_from"] = timing["steady_from"]
        if wildcards.thermostat == "white_noise":
            physics["beta"] = timing["beta"]
        if wildcards.thermostat == "gaussian" and wildcards.kernel == "hard_spheres":
            extra["histogram"] = {"shells": BEYOND["tail"]["shells"], "radius": BEYOND["tail"]["radius"]}
    label = f"beyond/{wildcards.thermostat}/{wildcards.kernel}/{wildcards.restitution}/n={wildcards.n}"
    return dsmc_run_config(label, physics, wildcards.N, wildcards.n, timing["t_end"], timing["observe_every"], **extra)


def beyond_disk_config(wildcards):
    """Run config of a hard-disk run, results/beyond/{thermostat}/hard_disks/alpha={alpha}/...: d = 2
    with the hard-disk impact law, moments up to M6 (a3), steady averages with the batch interval
    (honest for correlated rows; these runs reproduce no paper's intervals)."""
    law, value = wildcards.restitution.split("=")
    if law != "alpha" or wildcards.thermostat == "none":
        raise ValueError(f"{wildcards.thermostat}/{wildcards.restitution}: the hard-disk runs are steady, constant alpha")
    disks = BEYOND["disks_a2"]
    physics = {"alpha": float(value), "beta": disks["beta"] if wildcards.thermostat == "white_noise" else 0.0,
               "gamma": BEYOND["gamma"], "kernel": {"lambda": 1, "C": disks["C"]},
               "temperature0": BEYOND["temperature0"]}
    extra = {"thermostat": wildcards.thermostat, "dimension": 2, "geometry": "impact"}
    if wildcards.thermostat == "gaussian":
        extra["majorant"] = "pairwise"  # as for hard spheres: exact without kicks
    extra.update(moments=3, steady_from=disks["steady_from"], steady_ci="batch")
    label = f"beyond/{wildcards.thermostat}/hard_disks/{wildcards.restitution}/n={wildcards.n}"
    return dsmc_run_config(label, physics, wildcards.N, wildcards.n, disks["t_end"], disks["observe_every"], **extra)


def beyond_mixed_config(wildcards):
    """Run config of a mixture or rough-sphere run, results/beyond/{thermostat}/mixture-m{m1/m2}/...
    or .../rough-beta{beta}/...: steady hard spheres (lambda 1, C of beyond), constant alpha, with
    the timing of beyond.mixture or beyond.rough, steady averages with the batch interval, the
    majorant updated strictly (what the general-gas engine takes).  The
    mixture: species heavy (mass m1/m2, fraction x1) and light (mass 1), both of diameter 1; rough
    spheres: dsmc.roughness {beta, inertia: kappa}, spins started at the translational temperature."""
    law, value = wildcards.restitution.split("=")
    if law != "alpha" or wildcards.thermostat == "none":
        raise ValueError(f"{wildcards.thermostat}/{wildcards.restitution}: these runs are steady, constant alpha")
    mixture = wildcards.kernel.startswith("mixture-")
    item = BEYOND["mixture" if mixture else "rough"]
    physics = {"alpha": float(value), "beta": item.get("beta", 0.0) if wildcards.thermostat == "white_noise" else 0.0,
               "gamma": BEYOND["gamma"], "kernel": {"lambda": 1, "C": BEYOND["C"]},
               "temperature0": BEYOND["temperature0"]}
    extra = {"thermostat": wildcards.thermostat}
    if mixture:
        x1 = item["x1"]
        extra["species"] = [{"name": "heavy", "fraction": x1, "mass": float(wildcards.kernel[len("mixture-m"):]),
                             "diameter": 1.0},
                            {"name": "light", "fraction": round(1 - x1, 12), "mass": 1.0, "diameter": 1.0}]
    else:
        extra["roughness"] = {"beta": float(wildcards.kernel[len("rough-beta"):]), "inertia": item["kappa"]}
    # the general-gas engine: one exact bound per pair of species (the global majorant, its default),
    # updated strictly (it refuses the papers' truncated kernel and the pairwise majorant)
    physics["majorant_update"] = "strict"
    extra.update(steady_from=item["steady_from"], steady_ci="batch")
    label = f"beyond/{wildcards.thermostat}/{wildcards.kernel}/{wildcards.restitution}/n={wildcards.n}"
    return dsmc_run_config(label, physics, wildcards.N, wildcards.n, item["t_end"], item["observe_every"], **extra)


def beyond_mixed_runs(kind, thermostat, values, alphas, item):
    """The runs of the mixture (kind "mixture", values the mass ratios) or rough-sphere item
    ("rough", values the betas) for one thermostat."""
    kernels = [f"mixture-m{v}" if kind == "mixture" else f"rough-beta{v}" for v in values]
    return beyond_runs(thermostat, kernels, alphas, item["ensembles"], item["particles"])


localrules:
    beyond_run_config,


use rule run_config as beyond_run_config with:
    output:
        yaml="results/beyond/{thermostat}/{kernel}/{restitution}/N={N}/n={n}/run.yaml",
    log:
        "logs/beyond/{thermostat}/{kernel}/{restitution}/N={N}/n={n}/run_config.log",
    wildcard_constraints:
        thermostat="none|gaussian|white_noise",
        kernel=BEYOND_KERNELS,
        restitution="(alpha|delta)=[0-9.]+",
    params:
        run=beyond_run_config,


use rule run as beyond_run with:
    input:
        config=rules.beyond_run_config.output.yaml,
        granboltz=config["granboltz"],
    output:
        h5="results/beyond/{thermostat}/{kernel}/{restitution}/N={N}/n={n}/run.h5",
    log:
        "logs/beyond/{thermostat}/{kernel}/{restitution}/N={N}/n={n}/run.log",
    benchmark:
        "benchmarks/beyond/{thermostat}/{kernel}/{restitution}/N={N}/n={n}/run.tsv"
    wildcard_constraints:
        thermostat="none|gaussian|white_noise",
        kernel=BEYOND_KERNELS,
        restitution="(alpha|delta)=[0-9.]+",


HAFF, A2, TAIL, VISCO, DISKS = BEYOND["haff"], BEYOND["a2"], BEYOND["tail"], BEYOND["viscoelastic"], BEYOND["disks_a2"]
MIXTURE, ROUGH = BEYOND["mixture"], BEYOND["rough"]
HCS_SWPM = BEYOND["hcs_tail_swpm"]
if not (len(HCS_SWPM["radius"]) == len(HCS_SWPM["shells"]) == len(HCS_SWPM["alphas"])):
    raise ValueError("beyond.hcs_tail_swpm: radius and shells need one entry per alpha")
if not (_whole(HCS_SWPM["t_end"], HCS_SWPM["observe_every"]) and HCS_SWPM["steady_from"] < HCS_SWPM["t_end"]):
    raise ValueError("beyond.hcs_tail_swpm: t_end must be a whole multiple of observe_every, after steady_from")


def beyond_swpm_runs():
    """The SWPM runs of the HCS tail, one per alpha of beyond.hcs_tail_swpm."""
    return expand("results/beyond_swpm/gaussian/hard_spheres/alpha={alpha}/N={N}/n={n}/run.h5",
                  alpha=HCS_SWPM["alphas"], N=HCS_SWPM["ensembles"], n=HCS_SWPM["particles"])


def beyond_swpm_run_config(wildcards):
    """Run config of results/beyond_swpm/gaussian/hard_spheres/alpha={alpha}/N={N}/n={n}: hard
    spheres under the Gaussian thermostat with SWPM and importance splitting. The importance
    function is the theory tail exp(-A c) in r = |v - V|: rate A/v0 with A from the first-Sonine
    zeta (granboltz.reproduction.hcs_tail; only the variance depends on it), from split_radius out to R; the
    sweeps come every 1/(rate zeta R), the time the drift (zeta/2) r takes to move a particle at R
    by one e-fold of the importance function."""
    from granboltz.reproduction.hcs_tail import hcs_amplitude, sonine_cooling_rate, thermal_speed

    h = HCS_SWPM
    alpha = float(wildcards.alpha)
    k = [float(a) for a in h["alphas"]].index(alpha)
    R, T0 = float(h["radius"][k]), float(BEYOND["temperature0"])
    zeta = sonine_cooling_rate(alpha, BEYOND["gamma"], BEYOND["C"], T0, d=3)
    rate = hcs_amplitude(zeta, BEYOND["gamma"], BEYOND["C"], T0, d=3) / thermal_speed(T0)
    split = {"radius": float(h["split_radius"]), "rate": rate, "power": 1.0,
             "interval": 1.0 / (rate * zeta * R), "max_radius": R}
    weights = {"method": "swpm", "kappa": h["kappa"], "max_particles": int(h["max_particles"]),
               "reduction": h["reduction"], "split": split}
    physics = {"alpha": alpha, "beta": 0.0, "gamma": BEYOND["gamma"], "kernel": {"lambda": 1, "C": BEYOND["C"]},
               "temperature0": T0}
    label = f"beyond_swpm/gaussian/hard_spheres/alpha={wildcards.alpha}/n={wildcards.n}"
    run = dsmc_run_config(label, physics, wildcards.N, wildcards.n, h["t_end"], h["observe_every"],
                          thermostat="gaussian", histogram={"shells": int(h["shells"][k]), "radius": R, "center": "bulk"},
                          steady_from=h["steady_from"], weights=weights)
    run["dsmc"].pop("steady_ci")  # the batch interval: these runs reproduce no paper's intervals
    return run


localrules:
    beyond_swpm_run_config,


use rule run_config as beyond_swpm_run_config with:
    output:
        yaml="results/beyond_swpm/gaussian/hard_spheres/alpha={alpha}/N={N}/n={n}/run.yaml",
    log:
        "logs/beyond_swpm/gaussian/hard_spheres/alpha={alpha}/N={N}/n={n}/run_config.log",
    wildcard_constraints:
        alpha="[0-9.]+",
    params:
        run=beyond_swpm_run_config,


use rule run as beyond_swpm_run with:
    input:
        config=rules.beyond_swpm_run_config.output.yaml,
        granboltz=config["granboltz"],
    output:
        h5="results/beyond_swpm/gaussian/hard_spheres/alpha={alpha}/N={N}/n={n}/run.h5",
    log:
        "logs/beyond_swpm/gaussian/hard_spheres/alpha={alpha}/N={N}/n={n}/run.log",
    benchmark:
        "benchmarks/beyond_swpm/gaussian/hard_spheres/alpha={alpha}/N={N}/n={n}/run.tsv"
    wildcard_constraints:
        alpha="[0-9.]+",
    resources:
        mem_mb=swpm_mem_mb,


rule beyond_hcs_tail_swpm:
    input:
        runs=beyond_swpm_runs(),
    output:
        csv=report("results/tables/beyond_hcs_tail.csv", caption=item_caption("beyond_hcs_tail_swpm"), category="Beyond the papers"),
        summary="results/figures/beyond_hcs_tail_swpm.json",
    log:
        "logs/figures/beyond_hcs_tail_swpm.log",
    benchmark:
        "benchmarks/figures/beyond_hcs_tail_swpm.tsv"
    params:
        gamma=BEYOND["gamma"],
        C=BEYOND["C"],
        temperature0=BEYOND["temperature0"],
        fit=HCS_SWPM,
    script:
        "../scripts/beyond_hcs_tail_swpm.py"


rule beyond_haff:
    input:
        runs=beyond_runs("none", ["maxwell", "hard_spheres"], HAFF["alpha"], HAFF["ensembles"], HAFF["particles"]),
    output:
        csv=report("results/tables/beyond_haff.csv", caption=item_caption("beyond_haff"), category="Beyond the papers"),
        png=report("figures/beyond_haff.png", caption=item_caption("beyond_haff"), category="Beyond the papers"),
        pdf="figures/beyond_haff.pdf",
        summary="results/figures/beyond_haff.json",
    log:
        "logs/figures/beyond_haff.log",
    benchmark:
        "benchmarks/figures/beyond_haff.tsv"
    script:
        "../scripts/beyond_haff.py"


rule beyond_a2:
    input:
        runs=beyond_runs(["gaussian", "white_noise"], ["maxwell", "hard_spheres"], A2["alphas"], A2["ensembles"], A2["particles"]),
    output:
        csv=report("results/tables/beyond_a2.csv", caption=item_caption("beyond_a2"), category="Beyond the papers"),
        png=report("figures/beyond_a2.png", caption=item_caption("beyond_a2"), category="Beyond the papers"),
        pdf="figures/beyond_a2.pdf",
        summary="results/figures/beyond_a2.json",
    log:
        "logs/figures/beyond_a2.log",
    benchmark:
        "benchmarks/figures/beyond_a2.tsv"
    params:
        rel_tol=A2["rel_tol"],
        abs_floor=A2["abs_floor"],
        key_alphas=A2["key_alphas"],
    script:
        "../scripts/beyond_a2.py"


rule beyond_tail:
    input:
        run=beyond_runs("gaussian", "hard_spheres", TAIL["alpha"], TAIL["ensembles"], A2["particles"])[0],
    output:
        csv=report("results/tables/beyond_hcs_tail_profile.csv", caption=item_caption("beyond_tail"), category="Beyond the papers"),
        png=report("figures/beyond_hcs_tail.png", caption=item_caption("beyond_tail"), category="Beyond the papers"),
        pdf="figures/beyond_hcs_tail.pdf",
        summary="results/figures/beyond_hcs_tail.json",
    log:
        "logs/figures/beyond_hcs_tail.log",
    benchmark:
        "benchmarks/figures/beyond_hcs_tail.tsv"
    params:
        steady_from=A2["steady_from"],
        min_count=TAIL["min_count"],
        half_width=TAIL["half_width"],
        max_ci=TAIL["max_ci"],
    script:
        "../scripts/beyond_tail.py"


rule beyond_viscoelastic:
    input:
        runs=beyond_runs("none", "hard_spheres", VISCO["deltas"], VISCO["ensembles"], VISCO["particles"], "delta")
        + beyond_runs("none", "hard_spheres", [0.0], VISCO["elastic"]["ensembles"], VISCO["particles"], "delta"),
    output:
        csv=report("results/tables/beyond_viscoelastic.csv", caption=item_caption("beyond_viscoelastic"), category="Beyond the papers"),
        png=report("figures/beyond_viscoelastic.png", caption=item_caption("beyond_viscoelastic"), category="Beyond the papers"),
        pdf="figures/beyond_viscoelastic.pdf",
        summary="results/figures/beyond_viscoelastic.json",
    log:
        "logs/figures/beyond_viscoelastic.log",
    benchmark:
        "benchmarks/figures/beyond_viscoelastic.tsv"
    params:
        rows=VISCO["rows"],
        late_from=VISCO["late_from"],
    script:
        "../scripts/beyond_viscoelastic.py"


rule beyond_disks_a2:
    input:
        runs=beyond_runs(["gaussian", "white_noise"], "hard_disks", DISKS["alphas"], DISKS["ensembles"], DISKS["particles"]),
    output:
        csv=report("results/tables/beyond_disks_a2.csv", caption=item_caption("beyond_disks_a2"), category="Beyond the papers"),
        png=report("figures/beyond_disks_a2.png", caption=item_caption("beyond_disks_a2"), category="Beyond the papers"),
        pdf="figures/beyond_disks_a2.pdf",
        summary="results/figures/beyond_disks_a2.json",
    log:
        "logs/figures/beyond_disks_a2.log",
    benchmark:
        "benchmarks/figures/beyond_disks_a2.tsv"
    params:
        max_gap=DISKS["max_gap"],
    script:
        "../scripts/beyond_disks_a2.py"


rule beyond_mixture:
    input:
        runs=beyond_mixed_runs("mixture", "gaussian", MIXTURE["mass_ratios"], MIXTURE["alphas"], MIXTURE),
    output:
        csv=report("results/tables/beyond_mixture.csv", caption=item_caption("beyond_mixture"), category="Beyond the papers"),
        png=report("figures/beyond_mixture.png", caption=item_caption("beyond_mixture"), category="Beyond the papers"),
        pdf="figures/beyond_mixture.pdf",
        summary="results/figures/beyond_mixture.json",
    log:
        "logs/figures/beyond_mixture.log",
    benchmark:
        "benchmarks/figures/beyond_mixture.tsv"
    params:
        x1=MIXTURE["x1"],
    script:
        "../scripts/beyond_mixture.py"


rule beyond_rough:
    input:
        runs=beyond_mixed_runs("rough", "gaussian", ROUGH["tangential_betas"], ROUGH["hcs_alphas"], ROUGH)
        + beyond_mixed_runs("rough", "white_noise", ROUGH["tangential_betas"], ROUGH["white_noise_alphas"], ROUGH),
    output:
        csv=report("results/tables/beyond_rough.csv", caption=item_caption("beyond_rough"), category="Beyond the papers"),
        png=report("figures/beyond_rough.png", caption=item_caption("beyond_rough"), category="Beyond the papers"),
        pdf="figures/beyond_rough.pdf",
        summary="results/figures/beyond_rough.json",
    log:
        "logs/figures/beyond_rough.log",
    benchmark:
        "benchmarks/figures/beyond_rough.tsv"
    params:
        kappa=ROUGH["kappa"],
    script:
        "../scripts/beyond_rough.py"


for _rule, _name, _what in (
    (rules.beyond_haff, "Haff's law", "free cooling: Maxwell molecules T0 e^{−γπC(1−α²)t} exactly; hard spheres "
                                      "T0/(1 + t/t0)² with t0 from the cooling rate with the first-Sonine a2"),
    (rules.beyond_a2, "a2(α), both thermostats", "Sonine coefficient a2 of the HCS (Gaussian thermostat) and of the "
                                                 "white-noise steady state: hard spheres against van Noije–Ernst, "
                                                 "Maxwell molecules against the exact moment hierarchy"),
    (rules.beyond_tail, "HCS tail", "local exponent b(r) of the hard-sphere HCS distribution against the "
                                    "exponential tail b = 1"),
    (rules.beyond_viscoelastic, "Viscoelastic free cooling", "free cooling of viscoelastic hard spheres, "
                                "ε(g_n) = 1 − C1 δ g_n^{1/5} + C2 δ² g_n^{2/5}: T ∝ t^{−5/3} at late times "
                                "(Brilliantov–Pöschel), not Haff's t^{−2}; δ = 0 elastic, T constant"),
    (rules.beyond_disks_a2, "a2(α) of hard disks (d = 2)", "Sonine coefficients a2, a3 of hard disks (d = 2, impact "
                            "normals), HCS (Gaussian thermostat) and white noise, against van Noije–Ernst's d = 2 "
                            "first Sonine and the second Sonine approximation; white-noise T against the energy "
                            "balance"),
    (rules.beyond_mixture, "T1/T2 of a binary mixture", "temperature ratio T1/T2 of the HCS (Gaussian thermostat) of a "
                           "binary mixture of hard spheres (equal sizes, x1 = 1/2, m1/m2 = 2 and 4) against the "
                           "Maxwellian approximation of Garzó–Dufty (1999)"),
    (rules.beyond_rough, "θ of rough spheres", "ratio θ = T_rot/T_tr of rough hard spheres (κ = 2/5), HCS (Gaussian "
                         "thermostat) and white noise on the translational velocities, against the Maxwellian "
                         "approximation of Huthmann–Zippelius and Luding et al.")):
    _runs = _rule.input.runs if hasattr(_rule.input, "runs") else [_rule.input.run]
    report_item(BEYOND_PAPER, _name, _rule, "figure", _rule.output.png, _what, runs=_runs,
                run_rule=rules.beyond_run, summary=_rule.output.summary)
    report_item(BEYOND_PAPER, _name + " (table)", _rule, "table", _rule.output.csv, _what,
                compare="beyond_" + _rule.rule.name.split("_", 1)[1])

report_item(BEYOND_PAPER, "HCS tail, weighted particles", rules.beyond_hcs_tail_swpm, "table",
            rules.beyond_hcs_tail_swpm.output.csv,
            "exponential HCS tail f ~ exp(−A c^b) of hard spheres resolved to f/f(0) ≤ 1e−20 with weighted particles "
            "(SWPM, importance splitting along the Gaussian thermostat's drift): b against 1 and A against "
            "8πγC v0/ζ with the cooling rate ζ measured in the same run", runs=rules.beyond_hcs_tail_swpm.input.runs,
            run_rule=rules.beyond_swpm_run, compare="beyond_hcs_tail_swpm")
