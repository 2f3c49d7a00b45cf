"""Analytic reference solutions, used to validate the numerical solvers.

Modules::

    hertz     Hertz sphere on flat (thesis A.1).
    adhesion  Bradley, JKR, DMT and Maugis-Dugdale (thesis A.2; Johnson-Greenwood form).
    wavy      Rigid sphere on an axisymmetric wavy surface with a Dugdale zone (Guduru 2007,
              Paper A Eqs. 25-30, re-derived) and its JKR limit.
    periodic  Westergaard sinusoid, bisinusoidal (JGH 1985) asymptotes, Paper A bisinusoidal
              pull-off fit.
    rough     Greenwood-Williamson and Persson theories (thesis 2.1.1-2.1.2).
    mindlin   Cattaneo-Mindlin, Mindlin-Deresiewicz loops (corrected Eq. 2.27c) and the
              Spence (1975) stick ratio of normal loading with friction (dissimilar bodies).
    capillary Sphere-flat capillary force with films (thesis A.27-A.29) and the island rule's value.
    punch     Rounded and sharp flat punches (burls; Sneddon 1965), Kendall's flat-punch pull-off and
              the full-stick tangential stiffness 8 a/k.
    tangential_axisymmetric
              Partial slip of any axisymmetric contact of uncoupled bodies (Ciavarella-Jaeger:
              sphere, rounded and flat punch) and which reference a run's geometry admits.
    friction_loops
              The analytic loops and K_L references drawn beside a hysteresis run's summary.

Conventions: SI units, E* the composite modulus, forces positive when compressive, pull-off
forces NEGATIVE (``*_pull_off_magnitude`` helpers give |F|), approach positive when the bodies
are pushed together.
"""

from .adhesion import (
    MAUGIS_PER_TABOR, DMTSolution, JKRSolution, MaugisDugdaleCurve, MaugisDugdalePullOff,
    MaugisDugdaleSolution, bradley_pull_off, bradley_pull_off_magnitude, dmt, dmt_pull_off,
    dmt_pull_off_magnitude, dugdale_range, dugdale_stress, johnson_greenwood_pull_off_fit, jkr,
    jkr_pressure, jkr_pull_off, jkr_pull_off_magnitude, maugis_dugdale, maugis_dugdale_curve,
    maugis_dugdale_pressure, maugis_dugdale_pull_off, maugis_dugdale_pull_off_force,
    maugis_dugdale_pull_off_magnitude, maugis_dugdale_pull_off_point, maugis_dugdale_scales,
    maugis_from_tabor, maugis_parameter, tabor_from_maugis, tabor_parameter,
)
from .capillary import SphereFlatCapillary, sphere_flat_capillary, sphere_flat_island_force
from .hertz import HertzSolution, hertz, hertz_pressure
from .mindlin import (
    MindlinLoop, cattaneo_mindlin_displacement, cattaneo_mindlin_traction, cattaneo_stick_ratio,
    mindlin_compliance_k, mindlin_delta0, mindlin_deresiewicz_loop, mindlin_initial_stiffness,
    mindlin_loop_energy, mindlin_reloading_displacement, mindlin_reloading_stick_ratio,
    mindlin_reloading_stiffness, mindlin_unloading_displacement, mindlin_unloading_stick_ratio,
    mindlin_unloading_stiffness, mindlin_virgin_stiffness, spence_beta_over_mu,
    spence_stick_ratio, spence_traction,
)
from .periodic import (
    BisinusoidalAsymptotes, WestergaardSolution, bisinusoidal_asymptotes,
    bisinusoidal_curvature_radius, bisinusoidal_full_contact_pressure, bisinusoidal_pull_off_fit,
    bisinusoidal_pull_off_fit_magnitude, westergaard, westergaard_contact_fraction,
    westergaard_pressure,
)
from .punch import (
    FlatPunchSolution, RoundedPunchSolution, bonded_punch_stiffness, flat_punch, flat_punch_pressure,
    full_stick_stiffness, kendall_pull_off, kendall_pull_off_magnitude, rounded_punch, rounded_punch_approach,
    rounded_punch_force,
)
from .rough import (
    GreenwoodWilliamsonResult, greenwood_williamson, greenwood_williamson_F,
    persson_area_self_affine, persson_contact_area, persson_G, persson_P_sigma,
    persson_self_affine_C0, persson_self_affine_G, persson_self_affine_psd,
)
from .wavy import (
    GuduruCurve, GuduruSolution, guduru, guduru_cohesive_equation, guduru_curve,
    guduru_hertz_force, guduru_jkr_curve, guduru_parameters,
)

__all__ = [
    # hertz
    "HertzSolution", "hertz", "hertz_pressure",
    # adhesion
    "MAUGIS_PER_TABOR", "dugdale_stress", "dugdale_range", "tabor_parameter", "maugis_parameter",
    "maugis_from_tabor", "tabor_from_maugis",
    "bradley_pull_off", "bradley_pull_off_magnitude",
    "JKRSolution", "jkr", "jkr_pressure", "jkr_pull_off", "jkr_pull_off_magnitude",
    "DMTSolution", "dmt", "dmt_pull_off", "dmt_pull_off_magnitude",
    "johnson_greenwood_pull_off_fit",
    "MaugisDugdaleCurve", "MaugisDugdaleSolution", "MaugisDugdalePullOff",
    "maugis_dugdale_curve", "maugis_dugdale", "maugis_dugdale_pressure",
    "maugis_dugdale_pull_off", "maugis_dugdale_pull_off_point", "maugis_dugdale_pull_off_force",
    "maugis_dugdale_pull_off_magnitude", "maugis_dugdale_scales",
    # wavy
    "GuduruCurve", "GuduruSolution", "guduru", "guduru_curve", "guduru_jkr_curve",
    "guduru_cohesive_equation", "guduru_parameters", "guduru_hertz_force",
    # periodic
    "WestergaardSolution", "westergaard", "westergaard_pressure", "westergaard_contact_fraction",
    "BisinusoidalAsymptotes", "bisinusoidal_asymptotes", "bisinusoidal_full_contact_pressure",
    "bisinusoidal_curvature_radius", "bisinusoidal_pull_off_fit",
    "bisinusoidal_pull_off_fit_magnitude",
    # rough
    "greenwood_williamson_F", "GreenwoodWilliamsonResult", "greenwood_williamson",
    "persson_G", "persson_P_sigma", "persson_contact_area", "persson_self_affine_C0",
    "persson_self_affine_psd", "persson_self_affine_G", "persson_area_self_affine",
    # mindlin
    "mindlin_compliance_k", "mindlin_delta0", "mindlin_initial_stiffness",
    "cattaneo_stick_ratio", "cattaneo_mindlin_displacement", "cattaneo_mindlin_traction",
    "mindlin_virgin_stiffness", "mindlin_unloading_displacement", "mindlin_reloading_displacement",
    "mindlin_unloading_stick_ratio", "mindlin_reloading_stick_ratio",
    "mindlin_unloading_stiffness", "mindlin_reloading_stiffness", "mindlin_loop_energy",
    "MindlinLoop", "mindlin_deresiewicz_loop",
    "spence_beta_over_mu", "spence_stick_ratio", "spence_traction",
    # punch
    "RoundedPunchSolution", "rounded_punch", "rounded_punch_force", "rounded_punch_approach",
    "FlatPunchSolution", "flat_punch", "flat_punch_pressure", "kendall_pull_off", "kendall_pull_off_magnitude",
    "full_stick_stiffness", "bonded_punch_stiffness",
    # capillary
    "SphereFlatCapillary", "sphere_flat_capillary", "sphere_flat_island_force",
]
