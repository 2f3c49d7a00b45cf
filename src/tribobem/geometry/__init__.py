"""Geometry of the two bodies: shapes, random rough surfaces, measured topographies, statistics.

Sign convention (once, for the whole package): heights are in m and positive upward. Body 1 is
the lower body, body 2 the upper one. A *shape* (:mod:`.shapes`) is the height of body 2's lower
surface above ``z = 0`` (a sphere is ``r^2/(2R)``, 0 at its lowest point). The initial gap is
``h = h2 - h1`` (:func:`combine_gap`), with ``h1`` the topography of body 1 and ``h2`` body 2's
shape plus roughness.
"""

from .rough import gaussian_surface, johnson_quantiles, persson_psd, scale_to_rms, self_affine_surface
from .shapes import bisinusoidal, burl, cylinder, flat, sphere, wavy_sphere
from .textures import dimples, grooves, pillars, texture, waviness
from .stats import (
    acf,
    correlation_length,
    kurtosis,
    psd,
    rms_curvature,
    rms_height,
    rms_slope,
    skewness,
    summary,
)
from .topography import (
    DETREND_MODES,
    Topography,
    combine_gap,
    detrend_heights,
    gap_from_bodies,
    read_topography,
    unit_to_metres,
    validate_heights,
)

__all__ = [
    "flat",
    "sphere",
    "cylinder",
    "wavy_sphere",
    "bisinusoidal",
    "burl",
    "texture",
    "dimples",
    "pillars",
    "grooves",
    "waviness",
    "gaussian_surface",
    "self_affine_surface",
    "scale_to_rms",
    "persson_psd",
    "johnson_quantiles",
    "rms_height",
    "rms_slope",
    "rms_curvature",
    "skewness",
    "kurtosis",
    "psd",
    "acf",
    "correlation_length",
    "summary",
    "Topography",
    "read_topography",
    "detrend_heights",
    "validate_heights",
    "combine_gap",
    "gap_from_bodies",
    "unit_to_metres",
    "DETREND_MODES",
]
