"""The solver version: one integer, bumped on purpose when computed results change.

It is not the package version.  The package version changes with every release, also for
changes that leave every number as it was (a new CLI option, a faster FFT, a new example);
the solver version changes only when a change to the solvers, the interactions, the load
paths or a default of the scenario schema can change a result (a force, an area, a
pull-off, a stick ratio) beyond the solver tolerance.

Who reads it
------------
* :func:`tribobem.sweep.point_hash`: every sweep point's hash includes it (with the point's
  effective solver options), so a sweep restarted after a bump recomputes its points instead of
  gathering results of the old solver next to those of the new one.
* ``tribobem --version`` prints it beside the package version.

When to bump
------------
Bump :data:`SOLVER_VERSION` by one in the commit that changes results, and add a line to
the history below saying what changed.  Do not bump it for refactorings, speed-ups or new
features that reproduce the previous results to the solver tolerance (the validation
suite and the published-number checks, ``tribobem validate --ci``, are the evidence).

History
-------
1
    First numbered version: Polonsky-Keer with Paper A's Dugdale extension (explicit
    masks, the corrected force balance), the TangCG-type tangential solver with the
    normal-tangential coupling loop, as of issue 9.
2
    Pull-off (``solvers.normal_paths.pull_off``, run kind ``pulloff``): the unloading starts from the
    preload reached by displacement-controlled loading from the first touch
    (``solve_at_force``) instead of a force-controlled solve from zero pressure, and the curve
    includes that start; a missing preload means zero external load.  Sphere pull-offs move
    within the discrete-solution band (~1%); rough and periodic contacts may start on another
    branch.
3
    Tangential ramps to gross slip: the onset is bracketed by the extrapolation of the unused
    stick-zone friction instead of a bisection, and TangCG solves the states without stick
    itself.  The onset moves within its 1e-3 mu F0+ bracket, but the pre-sliding displacement,
    read at the bracket's state with stick, moves by up to 2 % on coarse grids (the design
    example), beyond the solver tolerance.
4
    Tangential force ramps in total slip on grids of >= 512^2 nodes: the onset is bracketed
    with displacement-controlled probes (``tangential_ramp(onset_by="auto")``) instead of
    force-controlled ones (smaller grids keep the force search and their results).  The
    onset moves within its 1e-3 mu F0+ bracket (the brackets overlap), and the pre-sliding
    displacement, read at the bracket's lower end, moves with that end: 0.2-0.6 % on the
    whole-burl ramp at 512^2-2048^2.
5
    Polonsky-Keer preconditions its CG once the contact set and the outside stresses have
    settled (``solve_normal(precondition=True)``).  It reached the plain iteration's
    equilibrium (the same contact and cohesive nodes, forces within the tolerance) in every
    case measured, and the adhesive friction loop's energies within 1e-6; a multistable
    adhesive contact may still end on another of its equilibria.  The coupling loop no longer
    takes a pass without pressure change as a contraction of 0 into the next step, which could
    stop that step after two passes at a pressure change of up to 6e-3.
6
    TangCG's search directions and preconditioner run in single precision on the NumPy backend
    with scipy.fft (results within the tangential tolerance of the double ones), and
    Polonsky-Keer under force control with an outside stress updates its displacement by kernel
    columns after a status change of a few nodes instead of recomputing it (round-off): the
    iteration paths of adhesive and coupled solves change at round-off level, which can move a
    multistable adhesive state to a neighbouring equilibrium.
7
    The coupling loop judges the pass it solves at the run's normal tolerance from the larger of
    the step's measured contraction and the last step's, and TangCG's loose solves (predictor,
    early passes) take their exact K q incrementally in single precision over larger changes
    (the fraction scaled with the tolerance): the coupled iteration paths change at the
    tolerances' level (the adhesive friction loop's energies by 1.4e-7, the same stick, contact
    and cohesive areas at every step).
8
    Measured scans are plane-detrended by default (``detrend = "height"``, was ``"center"``),
    so a scenario that reads a file without naming its detrend sees another surface; the
    library's ``solve_normal`` default is ``method = "auto"`` (NormCG without adhesion); a
    scenario's ``physical_size`` of a scan is in metres whatever the heights' unit; a design
    point's humid columns are its humid state.
"""

from __future__ import annotations

__all__ = ["SOLVER_VERSION"]

#: Version of the numerical results (see the module docstring for when to bump it).
SOLVER_VERSION: int = 8
