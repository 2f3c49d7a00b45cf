"""Published reference numbers that the validation compares against (copied, with their source).

These tables are the only published results :mod:`tribobem.validation` needs; they live here,
inside the installed package, so that ``tribobem validate`` never imports the paper studies
(the repository's top-level ``studies`` package, which is not installed).  The studies import
them from here.

:data:`PUBLISHED_CORNERS`
    The 16 corners of Paper A Table 1 in the project's published 625-case bisinusoidal study
    (``docs/data/bisinusoidal_pulloff.csv``; a test checks the copy).
:data:`PAPER_E_SMOOTH_REPULSIVE_FORCE`
    Paper E section 3.3: F0+ of the smooth interface at dgamma = 50 mJ/m^2.
"""

from __future__ import annotations

__all__ = ["PUBLISHED_CORNERS", "PAPER_E_SMOOTH_REPULSIVE_FORCE"]

#: (dgamma J/m^2, R_c m, E* Pa, k, published pull-off force N) of the 16 corners of Paper A
#: Table 1, copied from docs/data/bisinusoidal_pulloff.csv (tests check the copy).
PUBLISHED_CORNERS = (
    (0.03, 100e-6, 80e9, 0.1, -3.132743778e-05),    # lambda 0.93
    (0.03, 100e-6, 80e9, 0.9, -3.276983963e-05),    # lambda 0.93
    (0.03, 100e-6, 120e9, 0.1, -3.204227122e-05),   # lambda 0.71
    (0.03, 100e-6, 120e9, 0.9, -3.323545748e-05),   # lambda 0.71
    (0.03, 500e-6, 80e9, 0.1, -0.000149605888),     # lambda 1.59
    (0.03, 500e-6, 80e9, 0.9, -0.0001650773894),    # lambda 1.59
    (0.03, 500e-6, 120e9, 0.1, -0.0001525503859),   # lambda 1.21
    (0.03, 500e-6, 120e9, 0.9, -0.0001604692463),   # lambda 1.21
    (0.07, 100e-6, 80e9, 0.1, -6.986294744e-05),    # lambda 1.64
    (0.07, 100e-6, 80e9, 0.9, -7.650247839e-05),    # lambda 1.64
    (0.07, 100e-6, 120e9, 0.1, -7.097770163e-05),   # lambda 1.25
    (0.07, 100e-6, 120e9, 0.9, -7.605048275e-05),   # lambda 1.25
    (0.07, 500e-6, 80e9, 0.1, -0.0003301746814),    # lambda 2.80
    (0.07, 500e-6, 80e9, 0.9, -0.0004059644193),    # lambda 2.80
    (0.07, 500e-6, 120e9, 0.1, -0.0003413257071),   # lambda 2.14
    (0.07, 500e-6, 120e9, 0.9, -0.0003976396305),   # lambda 2.14
)

#: Paper E section 3.3: the smooth interface at dgamma = 50 mJ/m^2 has F0+ = 29.165 uN (N).
PAPER_E_SMOOTH_REPULSIVE_FORCE = 29.165e-6
