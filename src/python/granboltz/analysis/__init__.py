"""granboltz.analysis: estimators on arrays and runs (imports theory and output only).

Modules:
    finite_size     fit_finite_size: T(n) = T_inf + c/n over runs at several n
    local_exponent  the local exponent of a tail from log-binned shells
    tails           GRW05 §5.3 tail exponents
    tail_local      the local exponent against eq. (38) of the theory
    tail_swpm       the resolved depth of a weighted (SWPM) tail
    moment_checks   simulated speed moments against the exact Maxwell hierarchy; Crit(t) of RW05
"""
