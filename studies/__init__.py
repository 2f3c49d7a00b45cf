"""Parameter studies that reproduce the thesis' numerical results (built on the public API).

This package sits at the top of the repository, outside the installed ``tribobem`` package:
import it from the repository root (``python -c "import studies"``; the drivers in
``examples/studies/`` and the tests put the root on ``sys.path``).  ``tribobem validate`` never
imports it: the published numbers it needs are in :mod:`tribobem.validation.references`, the
computations in :mod:`tribobem.validation.bisinusoidal` and
:mod:`tribobem.validation.paper_e_model` (re-exported by :mod:`.bisinusoidal` and
:mod:`.paper_e`).  Measured topographies come from :func:`tribobem.data.topography_path`.

- :mod:`.bisinusoidal`: pull-off force of a bisinusoidal interface with Dugdale adhesion
  (Paper A section 6, Tables 1-2), and the fit ``F = a E*^beta R_c^(1+beta) dgamma^(1-beta) k^b``.
- :mod:`.rough_ball`: a smooth ball on a Gaussian rough flat scaled to several rms (Paper A
  section 7, Paper D section 3.2): pull-off, adhesive force and area ratio against rms.
- :mod:`.afm_pulloff`: pull-off of a colloidal probe on sub-windows ("spots") of a measured
  AFM scan (Paper C, vacuum state).
- :mod:`.paper_d`: gross-slip onset of an adhesive smooth ball (Paper D Table 1) with its
  resolution study; :mod:`.rough_slip`: a smooth ball on a rough flat (Paper D section 3.2).
- :mod:`.paper_e`: adhesive friction hysteresis of dissimilar bodies (Paper E section 3.2).
- :mod:`.paper_f`: polymer ball on a wafer, lateral stiffness at A, B, C (Paper F).
- :mod:`.humid_friction`: a smooth ball on a rough SiO2 flat against RH (static friction,
  pre-sliding, K_L at A/B/C, loop energy, F_cap beside the dry case); its results table is in
  its docstring (``python -m studies.humid_friction --out DIR``).
- :mod:`.burl_windows`: window versus whole (thesis recommendation 1): a whole rough burl
  against 2, 5 and 10 um windows at its centre and edge, free and periodic, at the nominal
  pressure the whole solve gives there; its table and answer are in its docstring
  (``python -m studies.burl_windows --out DIR``).
"""

from .bisinusoidal import (
    PAPER_A_FIT,
    PullOffFit,
    bisinusoidal_cell,
    bisinusoidal_gap,
    bisinusoidal_pull_off,
    fit_pull_off,
    pull_off_point,
)

__all__ = [
    "PAPER_A_FIT",
    "PullOffFit",
    "bisinusoidal_cell",
    "bisinusoidal_gap",
    "bisinusoidal_pull_off",
    "fit_pull_off",
    "pull_off_point",
]
