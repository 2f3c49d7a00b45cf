"""The analytic friction loop of a hysteresis run, read from its summary (summary.json): the
Mindlin-Deresiewicz loop of a smooth sphere (:mod:`tribobem.analytic.mindlin`), the rounded
punch of Ciavarella-Jaeger for a smooth burl
(:func:`tribobem.analytic.tangential_axisymmetric.lateral_reference`), and the name of the
reference beside the fitted lateral stiffness K_L.

The figures and the report of a hysteresis run overlay these on the computed loop; they take
the summary's step rows (``tangential_force_x``, ``displacement_x``, ``repulsive_force``,
``contact_area_compressive``; SI units) and its scenario echo ``inputs``, so ``tribobem plot``
re-makes them from the files alone.  Every function returns None (or a note) where the
reference does not apply, never raises on a summary it cannot use.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError

__all__ = ["loop_rows", "mindlin_reference", "mindlin_branches", "loop_reference", "reference_branches",
           "kl_reference", "kl_reference_values"]


def _num(v):
    """``v`` as a finite float, else None (a summary value: a number, None, a string ...)."""
    try:
        f = float(v)
    except (TypeError, ValueError):
        return None
    return f if np.isfinite(f) else None


def _friction_coefficient(summary: dict | None):
    """mu from the summary (run-level, else the scenario echo); None when unknown or not positive."""
    s = summary or {}
    mu = _num(s.get("friction_coefficient"))
    if mu is None:
        fr = (s.get("inputs") or {}).get("friction") or {}
        mu = _num(fr.get("coefficient")) if isinstance(fr, dict) else None
    return mu if mu is not None and mu > 0 else None


def loop_rows(summary: dict) -> list[dict]:
    """The step rows of a loop: those with a finite F_x and delta_x, when there are at least three.

    Parameters
    ----------
    summary : dict
        The run summary (summary.json) of a hysteresis run.

    Returns
    -------
    list of dict
        The rows (summary.json ``steps`` entries, SI units) in run order; empty for fewer than three.
    """
    rows = [r for r in (summary or {}).get("steps", []) or [] if isinstance(r, dict)
            and all(_num(r.get(k)) is not None for k in ("tangential_force_x", "displacement_x"))]
    return rows if len(rows) >= 3 else []


def _shear_moduli(summary: dict):
    """(1/G, nu) per body from the scenario echo; 1/G = 0 for a rigid body; None when unknown."""
    from .tangential_axisymmetric import body_compliances

    return body_compliances((summary or {}).get("inputs") or {})


def _smooth(summary: dict) -> bool:
    inp = (summary or {}).get("inputs") or {}
    for name in ("body1", "body2"):
        r = (inp.get(name) or {}).get("roughness") or {}
        if isinstance(r, dict) and r.get("kind", "none") not in ("none", None):
            return False
    return True


def mindlin_reference(summary: dict) -> dict | None:
    """The Mindlin-Deresiewicz loop of the run, when it applies: a sphere (paraboloid) on a
    flat or a sphere (:func:`tribobem.analytic.tangential_axisymmetric.reference_geometry`), smooth bodies with
    no normal-tangential coupling (identical materials, or beta = 0), a peak force below
    mu F0+, F0+ and the compressive contact area of the start row known.  Other shapes (a
    burl: :func:`loop_reference`) get None.

    Returns
    -------
    dict or None
        ``delta0`` (m), ``mu_p`` (mu F0+, N), ``peak`` (Q*, N), ``offset`` (delta_x of the start,
        m), ``radius`` (a, m), ``compliance`` (k = sum (2 - nu)/G, 1/Pa) and ``energy`` (the loop
        area per cycle, J).

    Parameters
    ----------
    summary : dict
        The run summary (summary.json) of a hysteresis run.
    """
    from .tangential_axisymmetric import reference_geometry

    rows = loop_rows(summary)
    mu = _friction_coefficient(summary)
    bodies = _shear_moduli(summary)
    if not rows or mu is None or bodies is None or not _smooth(summary):
        return None
    if reference_geometry((summary or {}).get("inputs") or {})[0] != "sphere":
        return None  # a sphere's loop applied to a punch is wrong by up to a factor of several in K_L
    (c1, n1), (c2, n2) = bodies
    beta = (1.0 - 2.0 * n1) * c1 - (1.0 - 2.0 * n2) * c2
    k = (2.0 - n1) * c1 + (2.0 - n2) * c2
    if k <= 0 or abs(beta) > 1e-6 * k:
        return None
    start = rows[0]
    P = _num(start.get("repulsive_force"))
    area = _num(start.get("contact_area_compressive")) or _num(start.get("contact_area"))
    if P is None or area is None or P <= 0 or area <= 0:
        return None
    a = float(np.sqrt(area / np.pi))
    mu_p = mu * P
    peak = _num(summary.get("peak_force"))
    if peak is None:
        peak = float(max(abs(float(r["tangential_force_x"])) for r in rows))
    if not (0 < peak < mu_p * (1 - 1e-9)):
        return None
    r = peak / mu_p
    energy = 9.0 * mu**2 * P**2 * k / (10.0 * a) * (1.0 - (1.0 - r) ** (5.0 / 3.0)
                                                     - 5.0 * r / 6.0 * (1.0 + (1.0 - r) ** (2.0 / 3.0)))
    return {"delta0": 3.0 * mu_p * k / (16.0 * a), "mu_p": mu_p, "peak": peak,
            "offset": float(start["displacement_x"]), "radius": a, "compliance": k, "energy": energy}


def mindlin_branches(ref: dict, n: int = 120):
    """(F, delta) of the Mindlin-Deresiewicz initial loading, unloading and reloading (m, N)."""
    d0, mp, qs, off = ref["delta0"], ref["mu_p"], ref["peak"], ref["offset"]
    base = (1.0 - qs / mp) ** (2.0 / 3.0)
    q = np.linspace(0.0, qs, n)
    load = d0 * (1.0 - (1.0 - q / mp) ** (2.0 / 3.0))
    qu = np.linspace(qs, -qs, 2 * n)
    unload = d0 * (2.0 * (1.0 - (qs - qu) / (2.0 * mp)) ** (2.0 / 3.0) - base - 1.0)
    reload = -d0 * (2.0 * (1.0 - (qs + qu[::-1]) / (2.0 * mp)) ** (2.0 / 3.0) - base - 1.0)
    return [(q, load + off), (qu, unload + off), (qu[::-1], reload + off)]


def loop_reference(summary: dict) -> dict | None:
    """The analytic loop matching the run's geometry, when there is one: Mindlin-Deresiewicz for
    a sphere (:func:`mindlin_reference`), the rounded punch of Ciavarella-Jaeger for a smooth
    burl of uncoupled bodies (:func:`tribobem.analytic.tangential_axisymmetric.lateral_reference`); None otherwise
    (:func:`kl_reference` says why).

    Parameters
    ----------
    summary : dict
        The run summary (summary.json) of a hysteresis run.

    Returns
    -------
    dict or None
        ``name`` (for legends and tables), ``mu_p`` (mu F0+, N), ``peak`` (Q*, N), ``offset``
        (delta_x of the start, m), ``energy`` (loop area per cycle, J) and, but for the sphere,
        ``model`` (:class:`~tribobem.analytic.tangential_axisymmetric.AxisymmetricPartialSlip`);
        the sphere's also has the keys of :func:`mindlin_reference`.
    """
    from .tangential_axisymmetric import lateral_reference, reference_geometry

    inp = (summary or {}).get("inputs") or {}
    if reference_geometry(inp)[0] == "sphere":
        ref = mindlin_reference(summary)
        return None if ref is None else dict(ref, name="Mindlin-Deresiewicz")
    rows = loop_rows(summary)
    mu = _friction_coefficient(summary)
    if not rows or mu is None:
        return None
    P = _num(rows[0].get("repulsive_force"))
    try:
        model, _ = lateral_reference(inp, P, mu)
    except (InputError, TypeError, ValueError, KeyError):  # an echo this reader cannot use
        return None
    if model is None:
        return None
    peak = _num(summary.get("peak_force"))
    if peak is None:
        peak = float(max(abs(float(r["tangential_force_x"])) for r in rows))
    if not (0 < peak < model.mu_p * (1 - 1e-9)):
        return None
    return {"name": model.name, "model": model, "mu_p": model.mu_p, "peak": peak,
            "offset": float(rows[0]["displacement_x"]), "energy": model.loop_energy(peak)}


def reference_branches(ref: dict, n: int = 120):
    """(F, delta) of the reference's initial loading, unloading and reloading (N, m)."""
    model = ref.get("model")
    if model is None:
        return mindlin_branches(ref, n)
    qs, off = ref["peak"], ref["offset"]
    q = np.linspace(0.0, qs, n)
    qu = np.linspace(qs, -qs, 2 * n)
    return [(q, model.virgin_displacement(q) + off), (qu, model.unloading_displacement(qu, qs) + off),
            (qu[::-1], model.reloading_displacement(qu[::-1], qs) + off)]


def kl_reference(summary: dict) -> tuple[str | None, str]:
    """Name of the analytic reference beside the fitted K_L of ``summary["lateral_stiffness"]``
    (its rows' ``reference_stiffness`` and ``reference_virgin_stiffness``), or None and why.

    Summaries written before the reference matched the geometry carry the sphere's law in
    ``mindlin_stiffness``: it is shown for a sphere only.

    Parameters
    ----------
    summary : dict
        The run summary (summary.json) of a hysteresis run.

    Returns
    -------
    (str or None, str)
        The reference's name ("Mindlin-Deresiewicz", "rounded punch (Ciavarella-Jaeger)") and
        an empty note, or None and a one-line note.
    """
    from .tangential_axisymmetric import reference_geometry

    s = summary or {}
    if "lateral_stiffness_reference" in s:
        name = s.get("lateral_stiffness_reference")
        return (name, "") if name else (None, str(s.get("lateral_stiffness_reference_note")
                                                   or "no analytic reference for this geometry"))
    kind, _, note = reference_geometry(s.get("inputs") or {})
    if kind == "sphere":
        return "Mindlin-Deresiewicz", ""
    return None, note or ("no analytic reference in this summary: its K_L reference is a sphere's, not this "
                          "geometry's (rerun the scenario for the rounded punch's)")


def kl_reference_values(row: dict) -> tuple[float, float]:
    """(branch slope, virgin slope) of the reference at one of the points A, B, C (N/m; nan when absent)."""
    def val(*keys):
        for key in keys:
            v = _num(row.get(key))
            if v is not None:
                return v
        return np.nan
    return val("reference_stiffness", "mindlin_stiffness"), val("reference_virgin_stiffness", "virgin_stiffness")
