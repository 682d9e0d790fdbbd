"""Report sections of RW05 §4.2: the steady-state Tables 3-6, the effort model and our repeated
steady runs."""

import math

from .numbers import DASH, LAMBDA_P, fix_typos, fl, num, pci, pm, verdict, z_score


def replica_inflation(extra):
    """Largest sd_ratio of the replica table among the extra tables (1 without one): how much
    the real spread of T_inf exceeds the nominal sigma of one run."""
    ratios = [fl(r["sd_ratio"]) for _, rows in extra for r in rows if "sd_ratio" in r]
    return max([1.0] + ratios)


def batch_sentence(ratios, factors):
    """The report's sentence on Conf against Conf_batch: the measured ratios Conf_batch / Conf
    and sqrt(2 tau_int), the part of them that is the standard error's own."""
    def spread(xs):
        return f"{sum(xs) / len(xs):.2f} on average ({min(xs):.2f}–{max(xs):.2f} over the rows)" if len(xs) > 1 \
            else f"{xs[0]:.2f}"

    text = ("The published Conf (and ours, computed as the paper does with dsmc.steady_ci: independent) treats the M "
            "observations of one run as independent, but consecutive observations are correlated. 'Conf batch' is "
            "the honest half-width of the same run and the same T∞ (the batch estimator, "
            "/steady/temperature_uncentred/batch/ci; with one ensemble per run, blocking over its M observations): "
            f"wider by a factor of {spread(ratios)}.")
    if factors:
        text += (f" Of that factor, √(2τ_int), {spread(factors)}, is the ratio of the two standard errors "
                 "(τ_int: the integrated autocorrelation time in observations); the rest is the Student-t quantile "
                 "of a standard error measured from the few independent blocks that one run holds.")
    return text


def compare_steady(name, ours, published, extra=(), **_):
    """RW05 Tables 3-6: T_inf, Error, Conf, CPU side by side; verdict from both Confs, widened
    by the real-to-nominal spread of the repeated runs (replica table) when there is one."""
    key = "method" if "method" in ours[0] else ("K" if "K" in ours[0] else None)
    f = replica_inflation(extra)
    pub_rows = fix_typos(name, published)
    pub = {r[key]: r for r in pub_rows} if key else {"": pub_rows[0]}
    header = [key or "scheme", "T∞ paper", "T∞ ours ± Conf", "Conf batch", "T expected", "Error paper", "Error ours",
              "CF paper", "CF ours", "Conf paper", "CPU paper", "CPU ours", "verdict (paper; expected)"]
    rows, z_all, z_exp, cpu_ratio, wider, factors = [], [], [], [], [], []
    for r in ours:
        k = r[key] if key else ""
        p = pub.get(k, {})
        T, conf, batch, tau = fl(r["T_inf"]), fl(r["Conf"]), fl(r.get("Conf_batch")), fl(r.get("tau_int"))
        if batch is not None and conf and math.isfinite(batch):
            wider.append(batch / conf)
            factors += [math.sqrt(2 * tau)] if tau is not None and math.isfinite(tau) else []
        z2 = z_score(T, fl(r["T_expected"]), f * conf, 0.0)
        z_exp.append(z2)
        zs = [z_score(T, fl(p["T_inf"]), f * conf, pci(p, "T_inf", f * fl(p["Conf"])))] if p else []
        z_all += zs
        if fl(p.get("CPU")) and fl(r.get("CPU")) and key:
            cpu_ratio.append(fl(r["CPU"]) / fl(p["CPU"]))
        rows.append([k or "no-splitting", num(fl(p.get("T_inf")), 5), pm(T, conf, 5), num(batch, 2),
                     num(fl(r["T_expected"]), 5),
                     num(fl(p.get("Error"))), num(fl(r["Error"])), num(fl(p.get("CF_Error"))), num(fl(r.get("CF_Error"))),
                     num(fl(p.get("Conf"))), num(fl(p.get("CPU"))), num(fl(r.get("CPU"))),
                     f"{verdict(zs[0]) if zs else DASH}; {verdict(z2)}"])
    text = ["T∞ is the average of |v|²/3 over the observations s_m > s0 of one run; Conf its 99.9 % half-width "
            "over those M observations (as the paper: the observations are taken as independent). "
            "'T expected' is the scheme's exact stationary mean (n → ∞: 2βΔt/(1 − e^{−kΔt}) for Euler, "
            "times e^{−kΔt/2} for Strang, 2β/k for no-splitting) plus the estimator's finite-n bias "
            "(the bulk velocity's random walk adds (T0 + 2βt)/n). σ-distances combine both Confs"
            + (f", each widened by {f:.2f}, the largest ratio of the real spread of T∞ over repeated runs to the "
               "nominal σ of one run (see 'Steady-state repeats' below): the M observations are correlated."
               if f > 1 else "."),
            *([batch_sentence(wider, factors)] if wider else []),
            "CPU: the simulator's own wall time (/provenance wall_seconds, one thread per run) relative to the "
            "no-splitting run; it depends on the relative cost of a kick and a collision in the implementation"
            + (": ours / paper = " + ", ".join(f"{x:.2f}" for x in cpu_ratio) if cpu_ratio else "") + "."]
    worst = max(z_all) if z_all else float("nan")
    short = (("agrees within the statistics" if worst <= LAMBDA_P else "differs in a row") + f" (max {worst:.1f}σ"
             f" from the paper, {max(z_exp):.1f}σ from the exact scheme value)")
    return [("table", header, rows), ("ul", text)], short


def compare_effort(name, ours, published=None, **_):
    """RW05 §4.2: counted events against the effort model (no published table)."""
    header = ["scheme", "K", "N_coll model", "N_coll counted", "N_kick model (paper)", "N_kick model (our grid)",
              "N_kick counted", "counted / model", "effort rel. (model)", "effort rel. (counted)", "CPU rel."]
    rows, dev = [], []
    for r in ours:
        coll = fl(r["N_coll"]) / fl(r["N_coll_model"])
        dev += [abs(coll - 1), abs(fl(r["kick_ratio"]) - 1)]
        rows.append([r["scheme"], r["K"] or DASH, r["N_coll_model"], r["N_coll"], r["N_kick_model"],
                     r["N_kick_model_grid"], r["N_kick"], f"{coll:.4f}, {fl(r['kick_ratio']):.4f}",
                     num(fl(r["effort_rel_model"])), num(fl(r["effort_rel"])), num(fl(r["CPU"]))])
    text = ["N_coll counts every event of the time counter (real and fictitious collisions; λ = 0 has no "
            "fictitious ones); the paper's no-splitting kick count nM uses the M observations averaged after s0, "
            "our runs observe at every t_m > 0 (column 'our grid'). Effort = N_coll + N_kick."]
    short = f"counted events within {100 * max(dev):.2f} % of the model"
    return [("table", header, rows), ("ul", text)], short


def compare_replicas(name, ours, published=None, **_):
    """Our check of the steady-state Conf: repeated runs, real spread against nominal sigma."""
    header = ["scheme", "K", "repeats", "mean T∞ ± s.e.", "T expected", "mean − expected", "sd of T∞",
              "nominal σ = Conf/λ_p", "sd / nominal σ", "batch σ", "sd / batch σ", "lag-1 autocorrelation"]
    rows = [[r["scheme"], r["K"] or DASH, r["replicas"], f"{num(fl(r['T_inf_mean']), 5)} ± {num(fl(r['T_inf_se']), 2)}",
             num(fl(r["T_expected"]), 5), f"{fl(r['z_expected']):+.1f} s.e.", num(fl(r["T_inf_sd"]), 3),
             num(fl(r["sigma_nominal"]), 3), f"{fl(r['sd_ratio']):.2f}", num(fl(r.get("sigma_batch")), 3),
             DASH if fl(r.get("sd_ratio_batch")) is None else f"{fl(r['sd_ratio_batch']):.2f}", f"{fl(r['rho1']):.2f}"] for r in ours]
    worst = max(abs(fl(r["z_expected"])) for r in ours)
    ratio = max(fl(r["sd_ratio"]) for r in ours)
    batch, labelled = [], []
    for r in ours:
        if fl(r.get("sd_ratio_batch")) is not None:
            batch.append(f"{fl(r['sd_ratio_batch']):.2f}")
            labelled.append(f"{batch[-1]} ({r['scheme']}" + (f", K = {r['K']})" if r["K"] else ")"))
    text = ["The mean over the repeats tests the exact stationary expectation to a few 10⁻⁴; the spread of T∞ "
            "between runs is the real statistical error of one run's T∞. A ratio above 1 means the M observations "
            "of one run are correlated (their lag-1 autocorrelation is in the last column), so Conf understates "
            "the error; the verdicts of Tables 3–6 widen both Confs by the largest ratio."]
    if batch:
        text.append("Batch σ is the batch estimator's standard error of one run (/steady/temperature_uncentred/"
                    "batch/sigma; with one ensemble per run, blocking over its M observations; root mean square over "
                    "the repeats): the real "
                    f"spread is {' and '.join(labelled)} × batch σ, where 1 means the interval a "
                    "single run reports is the right width.")
    also = f", {' and '.join(batch)} × batch σ" if batch else ""
    short = f"repeats agree with the exact expectation (max {worst:.1f} s.e.); real spread {ratio:.2f} × nominal σ{also}"
    if worst > LAMBDA_P:
        short = (f"**repeats differ from the exact expectation** ({worst:.1f} s.e.); real spread {ratio:.2f} × "
                 f"nominal σ{also}")
    return [("table", header, rows), ("ul", text)], short

