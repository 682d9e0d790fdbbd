"""granboltz.reproduction: the papers' tables and "Beyond the papers": table rows and verdicts.

Modules:
    dsmc             the DSMC runs of the GRW05/RW05 tables (temperature series, histogram, steady)
    dsmc_verdicts    the summary texts of the GRW05/RW05 DSMC figures (bands, curves, Crit, moments)
    grw05_tails      the verdicts of the GRW05 tail figures (eq. 38, local exponents, SWPM)
    tables           GRW05 Tables 1-2, RW05 Tables 1-2
    steady           RW05 Tables 3-6, repeated runs, the effort model
    tv06_tables, tv06_histograms   TV06 runs, tables and histograms
    tv06_verdicts    the verdicts of the TV06 figure summaries
    beyond           the report section "Beyond the papers": HCS a2, Haff's law, tails
    viscoelastic     viscoelastic free cooling, T ~ t^(-5/3)
    disks            a2, a3 of hard disks in d = 2
    mixtures         partial cooling rates, T_i/T of the HCS and white noise
    rough            rough spheres: theta = T_rot/T_tr
    hcs_tail         the HCS tail of a weighted run against the theory
"""
