"""Humid friction: kinds ``partial_slip`` and ``hysteresis`` with ``[humidity]``.

The capillary model of kind ``capillary`` (films levelled on each body's undeformed topography,
meniscus islands, Laplace pressure, water-filled and air-gap van der Waals terms, Dugdale
precedence) acts at every tangential step: the coupling loop calls the self-consistent capillary
normal solve (:class:`~tribobem.solvers.capillary.CapillaryModel`) where a dry run calls the
Dugdale one, so the islands are recomputed at every step and every coupling pass.  Shear acts
only where the contact is compressive (the tangential solver's friction bound mu p, p > 0), never
in a meniscus.  Under gross sliding the counterface (body 2) carries its film with it.

For every RH of ``[humidity] rh``, in the order given, one ramp (partial_slip) or one loop
(hysteresis) is run, its first solve warm-started from the previous RH's state at zero
tangential load.  Before them the same path is run dry (the scenario without ``[humidity]``:
Dugdale adhesion, if any, alone): its run-level values go to ``dry`` in summary.json, the
reference the humid values are read against.

Rows: every step of every RH, each with ``rh``, the films' mean thicknesses and the capillary
keys of its state (``capillary_force``, ``solid_solid_force``, ``water_solid_force``,
``adhesive_force_total``, ``wetted_area``, ``island_count``, ``kelvin_radius``,
``capillary_pressure``, ``island_iterations``, ``islands_converged``).  Run level: the kind's
named keys become lists in RH order (:data:`LIST_KEYS`); every other run-level value that differs
between RHs becomes a list too, one that does not stays a scalar.
"""

from __future__ import annotations

import warnings

import numpy as np

from ..errors import ConvergenceWarning
from ..solvers.capillary import CapillaryModel
from .capillary import capillary_options, films_at
from .kind import RunOutput
from .settings import SolverSettings

__all__ = ["capillary_model"]

#: Run-level keys that are lists in RH order in a humid run, per kind.
LIST_KEYS = {
    "partial_slip": ("static_friction_force", "static_friction_ratio", "presliding_displacement",
                     "onset_repulsive_force", "onset_adhesive_force"),
    "hysteresis": ("static_friction_force", "sliding_force", "dissipated_energy", "lateral_stiffness"),
}
#: Run-level keys of the dry reference kept under ``dry`` (with the kind's list keys).
DRY_KEYS = ("repulsive_force", "adhesive_force", "static_friction_ratio", "presliding_displacement",
            "zero_force_stick_ratio", "max_tangential_force", "dissipation_work", "gross_slip")

#: fields.nc maps a humid step adds (per kept state): name -> (dtype, attributes).
MENISCUS_FIELDS = {
    "meniscus": (np.int8, {"units": "1", "long_name": "active meniscus outside the contact (1) or not (0)"}),
    "film_thickness_2": (float, {"units": "m", "long_name": "water film on body 2 at its initial place"}),
}


def capillary_model(pb, rh: float, tol: float, settings: SolverSettings | None = None):
    """The capillary model of ``rh`` on the built scenario, with the films it rests on.

    Parameters
    ----------
    pb : Problem
        The built scenario with ``[humidity]``.
    rh : float
        Relative humidity (0..1).
    tol : float
        Film levelling tolerance (floored at
        :data:`~tribobem.runs.settings.FILM_TOLERANCE_FLOOR`).
    settings : SolverSettings, optional
        The run's solver settings: the model's normal solver (default: built from
        ``pb.scenario``).

    Returns
    -------
    (CapillaryModel, FilmResult, FilmResult)
    """
    f1, f2 = films_at(pb, rh, tol)
    return CapillaryModel(f1.thickness, f2.thickness, capillary_options(pb, rh, settings), pb.grid), f1, f2


def meniscus_fields(states, model: CapillaryModel | None) -> dict:
    """Per-state maps of a humid run (:data:`MENISCUS_FIELDS`), aligned with ``states``.

    Parameters
    ----------
    states : list of CoupledResult
        The coupled states kept for fields.nc.
    model : CapillaryModel or None
        The RH's model (None: a dry run, no maps).

    Returns
    -------
    dict
        name -> (list of maps, attributes), as :attr:`RunOutput.step_fields`.
    """
    if model is None:
        return {}
    men, film2 = [], []
    for s in states:
        cap = s.capillary
        contact = np.asarray(s.normal.contact, dtype=bool)
        active = np.asarray(cap.islands.active, dtype=bool) if cap is not None else np.zeros_like(contact)
        men.append((active & ~contact).astype(np.int8))
        film2.append(np.asarray(model.film2, dtype=float))
    return {"meniscus": (men, MENISCUS_FIELDS["meniscus"][1]),
            "film_thickness_2": (film2, MENISCUS_FIELDS["film_thickness_2"][1])}


class _Quiet:
    """A progress handler that shows nothing (the dry reference runs before the RH bar)."""

    def phase(self, description, total):
        pass

    def __call__(self, done, total):
        pass


def _same(a, b) -> bool:
    try:
        return bool(a == b) if not isinstance(a, (list, dict)) else a == b
    except (TypeError, ValueError):
        return False


def run_per_rh(pb, bar, run_one, kind: str, settings: SolverSettings | None = None) -> RunOutput:
    """Run ``run_one`` dry, then once per RH with the capillary model (module docstring).

    Parameters
    ----------
    pb : Problem
        The built scenario with ``[humidity]``.
    bar : progress handler
        ``bar.phase(description, total)`` and ``bar(done, total)``.
    run_one : callable
        ``run_one(pb, bar, interaction, initial, label, settings) -> (RunOutput, zero_state)``:
        one ramp or loop with the stress law ``interaction`` (a plain law or a CapillaryModel),
        its first solve warm-started from ``initial``; ``zero_state`` is its state at zero
        tangential load.
    kind : str
        ``"partial_slip"`` or ``"hysteresis"`` (its :data:`LIST_KEYS`).
    settings : SolverSettings, optional
        The run's solver settings, handed to every ``run_one`` (default: built from
        ``pb.scenario``); the films are levelled at its ``film_tolerance``.

    Returns
    -------
    RunOutput
        Rows, states and maps of every RH in order; run-level lists in RH order, ``rh`` and
        ``dry``.
    """
    hs = pb.humidity
    if settings is None:
        settings = SolverSettings.from_scenario(pb.scenario)
    list_keys = LIST_KEYS[kind]
    dry, _ = run_one(pb, _Quiet(), pb.interaction, None, "dry", settings)
    rows, results, tangential, labels, indices, notes = [], [], [], [], [], []
    step_fields: dict = {}
    cycle_fields: dict = {}
    runs = []
    warm = None
    for rh in hs.rh:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConvergenceWarning)
            model, f1, f2 = capillary_model(pb, rh, settings.film_tolerance, settings)
        out, warm = run_one(pb, bar, model, warm, f"RH {rh:g}", settings)
        first = len(rows)
        for r in out.rows:
            row = {"rh": float(rh), **r, "film_thickness_1": float(f1.mean_thickness),
                   "film_thickness_2": float(f2.mean_thickness)}
            if not (f1.converged and f2.converged):
                row["converged"] = False
            rows.append(row)
        results += out.results
        tangential += list(out.tangential or [])
        labels += [f"RH {rh:g} {lab}" for lab in out.labels]
        indices += [i + first if i >= 0 else -1 for i in out.indices]
        for name, (maps, attrs) in out.step_fields.items():
            step_fields.setdefault(name, ([], attrs))[0].extend(maps)
        notes += [f"RH {rh:g}: {w}" for w in out.warnings]
        notes += [f"RH {rh:g}, film on body{i}: {f.message}" for i, f in ((1, f1), (2, f2)) if not f.converged]
        runs.append(out.run)
        if out.cycle_fields:  # per-cycle maps: those of the last RH (the cycle axis is one loop's)
            cycle_fields = {name: (maps, {**attrs, "long_name": f"{attrs.get('long_name', name)}, at RH {rh:g}"})
                            for name, (maps, attrs) in out.cycle_fields.items()}
    run_level: dict = {"rh": [float(v) for v in hs.rh]}
    for key in dict.fromkeys(k for r in runs for k in r):
        values = [r.get(key) for r in runs]
        if key in list_keys or not all(_same(v, values[0]) for v in values[1:]):
            run_level[key] = values
        else:
            run_level[key] = values[0]
    for key in list_keys:
        run_level.setdefault(key, [None] * len(runs))
    run_level["dry"] = {k: dry.run.get(k) for k in (*list_keys, *DRY_KEYS) if k in dry.run}
    rep = _representative(labels, run_level, list_keys[0])
    return RunOutput(rows=rows, results=results, tangential=tangential or None, labels=labels, indices=indices,
                     run=run_level, warnings=notes + list(dry.warnings), step_fields=step_fields,
                     cycle_fields=cycle_fields,
                     step_coords={"rh": ([rows[i]["rh"] if i >= 0 else _rh_of(lab) for i, lab in zip(indices, labels)],
                                         {"units": "1", "long_name": "relative humidity"})},
                     representative=rep)


def _rh_of(label: str) -> float:
    return float(label.split()[1])


def _representative(labels, run_level, key) -> int | None:
    """The state ``output.fields = "last"`` keeps: the onset (or last state) of the RH with the
    largest static friction force."""
    if not labels:
        return None
    vals = [v if isinstance(v, (int, float)) and v is not None else -np.inf for v in run_level.get(key, [])]
    rhs = run_level["rh"]
    if not vals or all(v == -np.inf for v in vals):
        return len(labels) - 1
    rh = rhs[int(np.argmax(vals))]
    mine = [i for i, lab in enumerate(labels) if _rh_of(lab) == rh]
    onset = [i for i in mine if lab_is_onset(labels[i])]
    return (onset or mine)[-1]


def lab_is_onset(label: str) -> bool:
    """True for the label of a refined gross-slip onset state."""
    return label.endswith(" onset")
