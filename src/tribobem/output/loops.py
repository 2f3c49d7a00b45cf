"""The figure of a loop comparison (``tribobem compare-loop``): the measured and simulated
friction loops overlaid, and their last rising branches with the Paper F Eq. 3 fits and K_L at
the points A, B, C (:func:`tribobem.analysis.loops.compare_loops`)."""

from __future__ import annotations

import io
import math
from pathlib import Path

import numpy as np

from ..units import display_unit
from .atomic import atomic_write_bytes
from .plotting import legible

__all__ = ["comparison_figure"]


def comparison_figure(cmp, path, center: bool = True) -> Path:
    """Draw ``cmp`` (a :class:`~tribobem.analysis.loops.LoopComparison`) to ``path`` (PNG).

    Two panels: (a) the loops overlaid; (b) the pre-sliding branches from their turning points
    with the Eq. 3 fits and the points A, B, C.

    Parameters
    ----------
    cmp : LoopComparison
        The comparison; its ``figure`` is set to the written path.
    path : path-like
        The PNG file.
    center : bool
        Shift each loop so that its displacement range is centred on 0 (a measured path
        0 -> d_s and a simulated one -d_s/2 -> d_s/2 then overlay).

    Returns
    -------
    pathlib.Path
        The written file.
    """
    from matplotlib.figure import Figure

    sim, meas = cmp.simulated, cmp.measured
    fl, ll = display_unit(np.concatenate([sim.displacement, meas.displacement]), "length")
    ff, lf = display_unit(np.concatenate([sim.force, meas.force]), "force")
    fig = Figure(figsize=(11.5, 4.6), layout="constrained")
    ax1, ax2 = fig.subplots(1, 2)
    styles = {"simulated": dict(color="C0"), "measured": dict(color="C3")}
    for loop, fit in ((sim, cmp.simulated_fit), (meas, cmp.measured_fit)):
        off = 0.5 * (loop.displacement.max() + loop.displacement.min()) if center else 0.0
        c = styles[loop.kind]["color"]
        x = (loop.displacement - off) / fl
        if loop.kind == "simulated":
            ax1.plot(x, loop.force / ff, "-", color=c, lw=0.8, alpha=0.45)
            ax1.plot(x[fit.start:fit.end + 1], loop.force[fit.start:fit.end + 1] / ff, "o-", color=c, ms=2.5,
                     lw=1.4, label="simulated (last rising branch bold)")
        else:
            ax1.plot(x, loop.force / ff, ".", color=c, ms=2, alpha=0.6, label="measured")
        # branch from its turning point, fit and points
        sl = slice(fit.start, fit.end + 1)
        dd = (loop.displacement[sl] - fit.turn_displacement) / fl
        dF = (loop.force[sl] - fit.turn_force) / ff
        mk = "o" if loop.kind == "simulated" else "."
        ax2.plot(dd, dF, mk, color=c, ms=3 if loop.kind == "simulated" else 2, alpha=0.55)
        xf = np.linspace(0.0, loop.displacement[fit.fit_end] - fit.turn_displacement, 200)
        ax2.plot(xf / fl, (fit.force(xf + fit.turn_displacement) - fit.turn_force) / ff, "-", color=c, lw=1.6,
                 label=f"{loop.kind}: Eq. 3 fit, c1 = {fit.c1 / ff:.3g} {lf}, n = {fit.n:.2f}, {fit.points} points")
        for r in cmp.rows:
            p = r[loop.kind]
            if math.isfinite(p["displacement"]):
                ax2.plot((p["displacement"] - fit.turn_displacement) / fl, (p["force"] - fit.turn_force) / ff, "s",
                         color=c, mfc="white", ms=7, mew=1.5)
                ax2.annotate(f"{r['point']}: {p['stiffness'] / 1e3:.3g} kN/m",
                             ((p["displacement"] - fit.turn_displacement) / fl, (p["force"] - fit.turn_force) / ff),
                             xytext=(6, -10 if loop.kind == "measured" else 4), textcoords="offset points", fontsize=8,
                             color=c)
    ax1.set_xlabel(f"displacement{' - centre of its range' if center else ''} ({ll})")
    ax1.set_ylabel(f"tangential force ({lf})")
    ax1.set_title("(a) friction loops", fontsize=10)
    ax1.legend(fontsize=8)
    ax1.grid(alpha=0.3)
    right = max(loop.displacement[fit.fit_end] - fit.turn_displacement
                for loop, fit in ((sim, cmp.simulated_fit), (meas, cmp.measured_fit)))
    ax2.set_xlim(-0.03 * right / fl, 1.6 * right / fl)
    ax2.set_xlabel(f"displacement from the turning point ({ll})")
    ax2.set_ylabel(f"force from the turning point ({lf})")
    # three short lines: the panel is half the figure wide, and the title may not run past it
    ax2.set_title("(b) last rising branch from its turning point: Paper F Eq. 3 fits\n"
                  "of the pre-sliding part; K_L at A, B, C: F = -0.5, 0, +0.5 x scale\n"
                  f"(simulated: \u03bc F0+ = {sim.force_scale / ff:.4g} {lf}; "
                  f"measured: max|F| = {meas.force_scale / ff:.4g} {lf})", fontsize=10)
    ax2.legend(fontsize=8, loc="lower right")
    ax2.grid(alpha=0.3)
    legible(fig)  # 10 pt floor for the legends and the K_L annotations (drawn at 8 above)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=120)
    cmp.figure = atomic_write_bytes(Path(path), buf.getvalue())
    return cmp.figure
