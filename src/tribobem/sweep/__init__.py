"""Parameter sweeps: one scenario (or one library function) over a grid of parameters.

A sweep file (TOML) names what to run and what to vary::

    name = "dugdale-pulloff"                  # optional label
    scenario = "base.toml"                    # a scenario file, relative to this file ...
    # [base] ...                              # ... or an inline base scenario table
    # function = "package.module:callable"   # ... or a library function (keyword arguments)
    outputs = ["pull_off_force", "contact_area"]

    [parameters]                              # cartesian product of the lists
    "adhesion.work_of_adhesion" = ["30 mJ/m^2", "50 mJ/m^2"]
    "grid.n" = [64, 128]

    [[points]]                                # optional explicit points (combined with the
    "body2.shape.radius" = "10 um"            # product of [parameters] when both are given)

Each point is the base scenario with the point's dotted keys overridden.  It runs through
:func:`tribobem.scenario.run_scenario` (or the function) on a Dask cluster: a
``LocalCluster`` of processes by default, an existing scheduler given by its address, or
``"synchronous"`` (in-process, no Dask).  Every finished point is written at once and
atomically to ``OUTDIR/points/<hash>.json``, the hash being a stable digest of what the
point computes (runner, base and overrides, the point's effective solver options and the
solver version :data:`tribobem._solver_version.SOLVER_VERSION`), so a killed sweep loses no
finished point, a restart with the same spec computes only the points without a successful
record (failed points are retried), and a restart after a change of the solver (a bumped
solver version, a new default tolerance) recomputes every point instead of mixing old and new
results.  At the end every point is gathered into ``OUTDIR/results.nc``
(xarray; one dimension per parameter for a full grid, else a ``point`` dimension) and
``OUTDIR/results.csv``, both written atomically.

The package, one module per concern (each imports only the ones above it):

* :mod:`~tribobem.sweep.values`: canonical JSON, dotted keys and overrides, quantities;
* :mod:`~tribobem.sweep.point`: running one point (on a worker) and its record;
* :mod:`~tribobem.sweep.cache`: point hashes, the ``points/<hash>.json`` records, resuming;
* :mod:`~tribobem.sweep.spec`: the sweep file, its checks and its points;
* :mod:`~tribobem.sweep.results`: gathering into ``results.nc`` and ``results.csv``;
* :mod:`~tribobem.sweep.execute`: :func:`run_sweep`, synchronous or on Dask, progress, Ctrl-C;
* :mod:`~tribobem.sweep.command`: the ``tribobem sweep`` command.
"""

from .._solver_version import SOLVER_VERSION  # re-exported; the hashes read it at call time
from .cache import point_hash, read_points, solver_options
from .command import sweep_command
from .execute import SweepResult, run_sweep
from .results import gather
from .spec import SweepSpec, load_sweep
from .values import apply_overrides, flatten

__all__ = [
    # the sweep file
    "SweepSpec", "load_sweep",
    # running it
    "run_sweep", "SweepResult", "sweep_command",
    # points and hashes
    "point_hash", "solver_options", "SOLVER_VERSION", "read_points",
    # gathering
    "gather",
    # values
    "flatten", "apply_overrides",
]
