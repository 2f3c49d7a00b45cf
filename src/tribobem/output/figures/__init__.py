"""PNG figures of a run (matplotlib, Agg, no pyplot state), one module per figure family:

* :mod:`.maps`: topography, pressure map, contact map, profile along the row through the
  largest pressure;
* :mod:`.load_curve`: the force-approach curve;
* :mod:`.stickslip`: the tangential kinds' stick/slip maps with traction arrows, stick ratio and
  displacement against F_x/(mu F0+), stick ratio along a normal-load path;
* :mod:`.hysteresis`: the loop F_x - delta_x with Paper E's points and the analytic loop, the
  lateral stiffness at Paper F's points A, B, C, the dissipation maps, the maps at Paper E's
  points;
* :mod:`.humid_maps`: the stick/slip maps of a humid partial-slip run, one per RH;
* :mod:`.sets`: the figure sets a run kind declares (:data:`FIGURE_SETS`) and
  :func:`make_figures`, which draws them.

The humid friction curves per RH and the capillary figures are :mod:`tribobem.output.humid`'s
and :mod:`tribobem.output.capillary`'s; the analytic loops overlaid on a hysteresis loop are
:mod:`tribobem.analytic.friction_loops`' (re-exported here).

Every function takes the fields dataset (:mod:`tribobem.output.fields`) and/or the summary
dict, so ``tribobem plot RESULT`` re-makes the figures from the files alone.  Units are
chosen from the data (nm / µm, kPa / MPa / GPa, nN / µN).  Files are written atomically.
"""

from ...analytic.friction_loops import kl_reference, kl_reference_values, loop_reference, mindlin_reference
from .humid_maps import humid_stickslip_steps
from .hysteresis import (hysteresis_figures, hysteresis_loop_figure, loop_map_steps, loop_stickslip_figure, turning_point_letters)
from .load_curve import force_curve_figure
from .maps import profile_figure
from .sets import (FIGURE_NAMES, FIGURE_SETS, make_figures)
from .stickslip import (_segments, _stickslip_axes, meniscus_mask, stickslip_figure)

__all__ = [
    "FIGURE_NAMES", "FIGURE_SETS", "make_figures",
    # figures
    "profile_figure", "force_curve_figure", "stickslip_figure",
    "hysteresis_loop_figure", "loop_stickslip_figure", "hysteresis_figures",
    # what the figures show
    "turning_point_letters", "loop_map_steps", "meniscus_mask", "humid_stickslip_steps",
    # the analytic references drawn beside a run (tribobem.analytic.friction_loops)
    "mindlin_reference", "loop_reference", "kl_reference", "kl_reference_values",
    # private helpers the tests use
    "_segments", "_stickslip_axes",
]
