"""Partial slip of any axisymmetric contact of uncoupled bodies: the Ciavarella-Jaeger
superposition (the sphere, the rounded flat punch and the sharp flat punch).

Conventions
-----------
SI units.  A normal force ``P`` > 0 (N) is held while a tangential force ``Q`` (N, signed)
shifts the bodies tangentially by ``delta`` (m, same sign as ``Q``); ``mu`` is the Coulomb
friction coefficient.  The profile enters only through its frictionless normal solution:
the approach ``d(P')`` (m, ``d(0) = 0`` at the first touch) and the contact radius ``a(P')``
(m) at a normal force ``P'`` in ``[0, P]``.  ``E*`` is the composite modulus,
``1/E* = sum_i (1 - nu_i^2)/E_i`` (Pa), ``k = sum_i (2 - nu_i)/G_i`` the tangential compliance
of :func:`tribobem.analytic.mindlin.mindlin_compliance_k` (1/Pa; a rigid body adds 0).

The superposition (Ciavarella 1998; Jaeger 1998)
------------------------------------------------
For elastically similar bodies (no normal-tangential coupling, Dundurs' beta = 0) under a
constant normal force, the shear traction of the partial-slip state is ``mu`` times the
difference of two frictionless pressures of the same profile::

    q(r) = mu [p(r; P) - p(r; P_c)],      P_c = P - |Q|/mu,

the second one at the smaller normal force ``P_c`` whose contact radius is the stick radius,
``c = a(P_c)`` (Ciavarella, "Tangential loading of general three-dimensional contacts",
J. Appl. Mech. 65 (1998) 998; Jaeger, "A new principle in contact mechanics", J. Tribol. 120
(1998) 677).  Like Cattaneo-Mindlin it takes the traction along the load (exact for nu = 0,
the usual approximation otherwise).  The tangential displacement of the stick zone is then
the normal approach difference scaled by the ratio of the tangential to the normal
compliance of a circular patch (``k/8`` against ``1/(2 E*)`` per unit radius)::

    delta(Q) = (mu E* k / 4) [d(P) - d(P - |Q|/mu)]          (virgin curve, |Q| <= mu P)
    K(Q)     = dQ/d delta = 8 c / k,   c = a(P - |Q|/mu)      (the stick radius)

This is the method of dimensionality reduction's ``F_x(u) = mu [F_N(d) - F_N(d - G* u/(mu
E*))]`` (Popov and Hess 2015; MDR's ``G* = 4/k``), read as ``delta`` against ``Q``; the stiffness
follows from ``dP/dd = 2 E* a`` (Sneddon).  Gross slip sets in at ``|Q| = mu P``, at the shift
``delta_s = mu E* k d(P) / 4``.

Unloading and reloading at constant P follow Masing's rule (the superposition holds for the
increments from a turning point, Mindlin and Deresiewicz 1953; Jaeger 1998)::

    unloading from +Q*:  delta = delta(Q*) - 2 delta((Q* - Q)/2),   K = K((Q* - Q)/2)
    reloading from -Q*:  delta = -delta(Q*) + 2 delta((Q* + Q)/2),  K = K((Q* + Q)/2)
    loop energy:         W = 4 Q* delta(Q*) - 8 int_0^Q* delta(Q) dQ

Profiles (:func:`sphere_partial_slip`, :func:`rounded_punch_partial_slip`,
:func:`flat_punch_partial_slip`):

* sphere (paraboloid, radius R): ``a(P') = a (P'/P)^(1/3)``, ``d = a^2/R``; the formulas above
  are Cattaneo-Mindlin and Mindlin-Deresiewicz exactly (``delta_s = 3 mu P k/(16 a)``, ``K =
  (8 a/k)(1 - |Q|/(mu P))^(1/3)``; :mod:`tribobem.analytic.mindlin`).
* rounded flat punch (flat top of radius b, edge radius R, optional crown; the burl):
  ``a(P')``, ``d(P')`` of :func:`tribobem.analytic.punch.rounded_punch` (``a >= b`` for every
  ``P' >= 0`` without a crown).  The stick radius never shrinks below the flat's radius: ``K``
  falls from ``8 a/k`` to ``8 b/k`` as ``|Q| -> mu P`` and the whole flat slips at once there
  (``K`` then drops to 0).  A sphere's law applied to a burl (``c/a = (1 - |Q|/(mu P))^(1/3)``)
  puts K far too low near the turning points.
* sharp flat punch (radius b): ``d = P'/(2 b E*)``, ``a = b``: the punch sticks fully until
  gross slip, ``delta = k Q/(8 b)``, ``K = 8 b/k`` at every ``|Q| < mu P`` and no hysteresis
  below gross slip (``W = 0``).

With normal-tangential coupling (dissimilar bodies, beta != 0) the shear changes the pressure
and the superposition does not hold; there is no closed form then (the sphere's Mindlin
formulas are the uncoupled approximation, :mod:`tribobem.analytic.mindlin`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np
from scipy.integrate import quad

from ..errors import InputError
from .punch import rounded_punch

__all__ = ["AxisymmetricPartialSlip", "sphere_partial_slip", "rounded_punch_partial_slip",
           "flat_punch_partial_slip", "reference_geometry", "lateral_reference", "body_compliances"]

_TOL = 1e-12     # relative slack on |Q| <= mu P and |Q| <= Q*


def _pos(name: str, value) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(name, f"must be a finite number > 0, got {value!r}") from None
    if not (math.isfinite(v) and v > 0):
        raise InputError(name, f"must be a finite number > 0, got {value!r}")
    return v


def _out(x):
    x = np.asarray(x, dtype=float)
    return float(x) if x.ndim == 0 else x


@dataclass(frozen=True)
class AxisymmetricPartialSlip:
    """Tangential partial slip of an axisymmetric contact at constant normal force (uncoupled).

    Built from the profile's frictionless normal solution (module docstring); the factories
    :func:`sphere_partial_slip`, :func:`rounded_punch_partial_slip` and
    :func:`flat_punch_partial_slip` fill it in.

    Attributes
    ----------
    force : float
        Normal force ``P`` (N), > 0.
    mu : float
        Friction coefficient, > 0.
    k : float
        Tangential compliance ``sum (2 - nu_i)/G_i`` (1/Pa).
    E_star : float
        Composite modulus (Pa) of the normal solution.
    approach : callable
        ``d(P')`` (m) for ``0 <= P' <= P``, ``d(0) = 0``.
    contact_radius : callable
        ``a(P')`` (m) for ``0 <= P' <= P``.
    name : str
        The reference's name in tables and legends.
    """

    force: float
    mu: float
    k: float
    E_star: float
    approach: Callable[[float], float]
    contact_radius: Callable[[float], float]
    name: str = "axisymmetric (Ciavarella-Jaeger)"

    # ------------------------------------------------------------------ helpers
    @property
    def mu_p(self) -> float:
        """``mu P`` (N), the force of gross slip."""
        return self.mu * self.force

    def _abs_force(self, Q, name="Q"):
        Q = np.asarray(Q, dtype=float)
        if not np.all(np.isfinite(Q)):
            raise InputError(name, f"must be finite, got {Q!r}")
        if np.any(np.abs(Q) > self.mu_p * (1.0 + _TOL)):
            raise InputError(name, f"|{name}| must not exceed mu P = {self.mu_p:g} N (gross sliding)")
        return np.clip(np.abs(Q), 0.0, self.mu_p)

    def _amplitude(self, Q_star) -> float:
        Qs = float(Q_star)
        if not math.isfinite(Qs) or Qs <= 0 or Qs > self.mu_p * (1.0 + _TOL):
            raise InputError("Q_star", f"must be finite, > 0 and at most mu P = {self.mu_p:g} N, got {Q_star!r}")
        return min(Qs, self.mu_p)

    def _branch(self, Q, Qs):
        Q = np.asarray(Q, dtype=float)
        if not np.all(np.isfinite(Q)) or np.any(np.abs(Q) > Qs * (1.0 + _TOL)):
            raise InputError("Q", f"must lie in [-Q*, Q*] = [{-Qs:g}, {Qs:g}] N")
        return np.clip(Q, -Qs, Qs)

    def _shift(self, q: float) -> float:
        """Virgin shift (m) at the force magnitude ``q`` in [0, mu P]."""
        rest = max(self.force - q / self.mu, 0.0)
        return 0.25 * self.mu * self.E_star * self.k * (self.approach(self.force) - self.approach(rest))

    def _slope(self, q: float) -> float:
        """Virgin stiffness (N/m) at the force magnitude ``q``: 8 c/k, 0 in gross slip."""
        if q >= self.mu_p * (1.0 - _TOL):
            return 0.0
        return 8.0 * self.contact_radius(self.force - q / self.mu) / self.k

    # ------------------------------------------------------------------ virgin curve
    @property
    def slip_displacement(self) -> float:
        """Shift at the onset of gross slip, ``delta_s = mu E* k d(P)/4`` (m)."""
        return self._shift(self.mu_p)

    @property
    def initial_stiffness(self) -> float:
        """``K(0) = 8 a/k`` (N/m), ``a`` the contact radius at P."""
        return self._slope(0.0)

    def stick_radius(self, Q):
        """Stick radius ``c = a(P - |Q|/mu)`` on the virgin curve (m); 0 at gross slip.

        Parameters
        ----------
        Q : float or array_like
            Tangential force (N), ``|Q| <= mu P``.

        Returns
        -------
        float or ndarray
            c (m), shape of ``Q``.
        """
        q = self._abs_force(Q)
        return _out(np.vectorize(lambda x: 0.0 if x >= self.mu_p * (1.0 - _TOL)
                                 else self.contact_radius(self.force - x / self.mu))(q))

    def virgin_displacement(self, Q):
        """Shift on the virgin curve ``delta = sign(Q) (mu E* k/4) [d(P) - d(P - |Q|/mu)]`` (m).

        Parameters
        ----------
        Q : float or array_like
            Tangential force (N), ``|Q| <= mu P``.

        Returns
        -------
        float or ndarray
            delta (m), shape and sign of ``Q``.
        """
        Q = np.asarray(Q, dtype=float)
        q = self._abs_force(Q)
        return _out(np.sign(Q) * np.vectorize(self._shift)(q))

    def virgin_stiffness(self, Q):
        """Slope ``dQ/d delta = 8 c/k`` of the virgin curve (N/m); 0 at ``|Q| = mu P``.

        Parameters
        ----------
        Q : float or array_like
            Tangential force (N), ``|Q| <= mu P``.

        Returns
        -------
        float or ndarray
            K (N/m), shape of ``Q``.
        """
        q = self._abs_force(Q)
        return _out(np.vectorize(self._slope)(q))

    # ------------------------------------------------------------------ Masing branches
    def unloading_displacement(self, Q, Q_star):
        """Shift on the branch unloading from +Q* (m): ``delta(Q*) - 2 delta((Q* - Q)/2)``.

        Parameters
        ----------
        Q : float or array_like
            Tangential force (N) in [-Q*, Q*].
        Q_star : float
            Turning-point amplitude (N), ``0 < Q* <= mu P``.

        Returns
        -------
        float or ndarray
            delta (m), shape of ``Q``.
        """
        Qs = self._amplitude(Q_star)
        x = self._branch(Q, Qs)
        return _out(self._shift(Qs) - 2.0 * np.vectorize(self._shift)((Qs - x) / 2.0))

    def reloading_displacement(self, Q, Q_star):
        """Shift on the branch reloading from -Q* (m): ``-delta(Q*) + 2 delta((Q* + Q)/2)``.

        Parameters
        ----------
        Q : float or array_like
            Tangential force (N) in [-Q*, Q*].
        Q_star : float
            Turning-point amplitude (N), ``0 < Q* <= mu P``.

        Returns
        -------
        float or ndarray
            delta (m), shape of ``Q``.
        """
        # Masing: the reloading branch is the unloading branch mirrored through the origin.
        return _out(-np.asarray(self.unloading_displacement(-np.asarray(Q, dtype=float), Q_star)))

    def unloading_stiffness(self, Q, Q_star):
        """Slope of the branch unloading from +Q*, ``K((Q* - Q)/2)`` (N/m).

        Parameters
        ----------
        Q : float or array_like
            Tangential force (N) in [-Q*, Q*].
        Q_star : float
            Turning-point amplitude (N), ``0 < Q* <= mu P``.

        Returns
        -------
        float or ndarray
            K (N/m), shape of ``Q``; ``8 a/k`` at the turning point.
        """
        Qs = self._amplitude(Q_star)
        x = self._branch(Q, Qs)
        return _out(np.vectorize(self._slope)((Qs - x) / 2.0))

    def reloading_stiffness(self, Q, Q_star):
        """Slope of the branch reloading from -Q*, ``K((Q* + Q)/2)`` (N/m).

        Parameters
        ----------
        Q : float or array_like
            Tangential force (N) in [-Q*, Q*].
        Q_star : float
            Turning-point amplitude (N), ``0 < Q* <= mu P``.

        Returns
        -------
        float or ndarray
            K (N/m), shape of ``Q``; ``8 a/k`` at the turning point -Q*.
        """
        return self.unloading_stiffness(-np.asarray(Q, dtype=float), Q_star)

    def loop_energy(self, Q_star) -> float:
        """Energy dissipated per cycle +-Q* (J): ``4 Q* delta(Q*) - 8 int_0^Q* delta dQ``.

        Parameters
        ----------
        Q_star : float
            Amplitude (N), ``0 < Q* <= mu P``.

        Returns
        -------
        float
            W (J); 0 for a contact in full stick (a linear virgin curve).
        """
        Qs = self._amplitude(Q_star)
        integral, _ = quad(self._shift, 0.0, Qs, epsabs=0.0, epsrel=1e-11, limit=200)
        # the area between the Masing branches; the reloading branch lies above the unloading one
        return float(max(4.0 * Qs * self._shift(Qs) - 8.0 * integral, 0.0))


def sphere_partial_slip(*, force, mu, k, E_star=None, radius=None, contact_radius=None) -> AxisymmetricPartialSlip:
    """The sphere (paraboloid): Cattaneo-Mindlin and Mindlin-Deresiewicz.

    Parameters
    ----------
    force, mu, k : float
        Normal force (N), friction coefficient, tangential compliance (1/Pa).
    E_star : float, optional
        Composite modulus (Pa); needed with ``radius``.  With ``contact_radius`` it cancels
        (``E* d(P') = (3 P/(4 a)) (P'/P)^(2/3)``) and may be left out.
    radius : float, optional
        Composite radius ``R`` (m).  Give exactly one of ``radius`` and ``contact_radius``.
    contact_radius : float, optional
        Contact radius ``a`` at ``force`` (m): the reference then matches a contact of that
        radius (e.g. the measured compressive area ``pi a^2``), as the Mindlin formulas of
        :mod:`tribobem.analytic.mindlin` do.

    Returns
    -------
    AxisymmetricPartialSlip
    """
    P, mu, k = _pos("force", force), _pos("mu", mu), _pos("k", k)
    if (radius is None) == (contact_radius is None):
        raise InputError("sphere_partial_slip", "give exactly one of radius= and contact_radius=")
    if contact_radius is not None:
        a = _pos("contact_radius", contact_radius)
        Es = 1.0 if E_star is None else _pos("E_star", E_star)
        R = 4.0 * Es * a**3 / (3.0 * P)
    else:
        R = _pos("radius", radius)
        if E_star is None:
            raise InputError("E_star", "required with radius= (the Hertz contact radius depends on it)")
        Es = _pos("E_star", E_star)
        a = (3.0 * P * R / (4.0 * Es)) ** (1.0 / 3.0)

    def radius_of(p):
        return a * np.cbrt(max(p, 0.0) / P)

    def approach_of(p):
        return radius_of(p) ** 2 / R

    return AxisymmetricPartialSlip(P, mu, k, Es, approach_of, radius_of, "Mindlin-Deresiewicz")


def rounded_punch_partial_slip(*, force, mu, k, E_star, flat_radius, edge_radius,
                               crown=None) -> AxisymmetricPartialSlip:
    """The rounded flat punch (the burl): Ciavarella-Jaeger on the normal solution of
    :func:`tribobem.analytic.punch.rounded_punch`.

    Parameters
    ----------
    force, mu, k : float
        Normal force (N), friction coefficient, tangential compliance (1/Pa).
    E_star : float
        Composite modulus (Pa).
    flat_radius : float
        Radius ``b`` of the flat top (m), >= 0.
    edge_radius : float
        Radius ``R`` of the rounded edge (m), > 0.
    crown : float, optional
        Radius of a spherical crown over the whole punch (m); None: a flat top.

    Returns
    -------
    AxisymmetricPartialSlip
        Named "rounded punch (Ciavarella-Jaeger)".
    """
    P, mu, k, Es = _pos("force", force), _pos("mu", mu), _pos("k", k), _pos("E_star", E_star)
    kw = {"flat_radius": flat_radius, "edge_radius": edge_radius, "E_star": Es, "crown": crown}
    rounded_punch(force=P, **kw)  # checks the geometry once, naming the argument

    def approach_of(p):
        return rounded_punch(force=max(p, 0.0), **kw).approach

    def radius_of(p):
        return rounded_punch(force=max(p, 0.0), **kw).contact_radius

    return AxisymmetricPartialSlip(P, mu, k, Es, approach_of, radius_of, "rounded punch (Ciavarella-Jaeger)")


def flat_punch_partial_slip(*, force, mu, k, E_star, radius) -> AxisymmetricPartialSlip:
    """The sharp flat punch of radius ``b``: full stick until gross slip, ``K = 8 b/k``.

    Parameters
    ----------
    force, mu, k : float
        Normal force (N), friction coefficient, tangential compliance (1/Pa).
    E_star : float
        Composite modulus (Pa).
    radius : float
        Punch radius ``b`` (m), > 0.

    Returns
    -------
    AxisymmetricPartialSlip
        Named "flat punch (full stick)"; ``delta = k Q/(8 b)``.
    """
    P, mu, k, Es, b = _pos("force", force), _pos("mu", mu), _pos("k", k), _pos("E_star", E_star), _pos("radius", radius)

    def approach_of(p):
        return max(p, 0.0) / (2.0 * b * Es)

    def radius_of(p):
        return b

    return AxisymmetricPartialSlip(P, mu, k, Es, approach_of, radius_of, "flat punch (full stick)")


# ----------------------------------------------------------------------------- which reference a run admits
def _body_elastic(body: dict, name: str):
    """(E, nu) of a body of the scenario echo (E = inf when rigid); None when not readable."""
    if body.get("rigid"):
        return math.inf, 0.5
    try:
        E, nu = float(body.get("E")), float(body.get("nu"))
    except (TypeError, ValueError):
        return None
    if not (math.isfinite(E) and E > 0 and -1.0 < nu <= 0.5):
        return None
    return E, nu


def _compliances(el):
    """(1/G (1/Pa), nu) of each (E, nu) of :func:`_body_elastic`; 1/G = 0 for a rigid body."""
    return [(0.0 if math.isinf(E) else 2.0 * (1.0 + nu) / E, nu) for E, nu in el]


def body_compliances(inputs: dict):
    """(1/G, nu) of body1 and body2 of a scenario echo (1/G in 1/Pa, 0 for a rigid body).

    Parameters
    ----------
    inputs : dict
        The scenario echo of a summary (``summary["inputs"]``, SI numbers).

    Returns
    -------
    list of (float, float) or None
        None when a body's modulus or Poisson ratio is not readable.
    """
    el = [_body_elastic((inputs or {}).get(n) or {}, n) for n in ("body1", "body2")]
    return None if None in el else _compliances(el)


def reference_geometry(inputs: dict) -> tuple[str | None, dict, str]:
    """Which analytic tangential reference the bodies' shapes admit.

    Parameters
    ----------
    inputs : dict
        The scenario echo of a summary (``summary["inputs"]``, SI numbers), or
        ``Scenario.model_dump(mode="json")``.

    Returns
    -------
    (kind, parameters, note)
        ``kind`` is ``"sphere"`` (``parameters = {"radius": R}``, the composite radius of one or
        two paraboloids, a wavy sphere of amplitude 0 included), ``"rounded_punch"`` (a burl on a
        flat: ``flat_radius``, ``edge_radius``, ``crown``; m) or None, with ``note`` saying why
        (one line).  Roughness, textures and coupling are not looked at here
        (:func:`lateral_reference`).
    """
    shapes = []
    for name in ("body1", "body2"):
        s = ((inputs or {}).get(name) or {}).get("shape") or {"kind": "flat"}
        kind = s.get("kind", "flat")
        if kind == "wavy_sphere" and not float(s.get("amplitude") or 0.0):
            kind = "sphere"  # a wavy sphere without waves is the paraboloid
        if kind != "flat":
            shapes.append((name, kind, s))
    kinds = sorted(k for _, k, _ in shapes)
    if kinds and all(k == "sphere" for k in kinds):
        curv = sum(1.0 / float(s["radius"]) for _, _, s in shapes)
        return "sphere", {"radius": 1.0 / curv}, ""
    if kinds == ["burl"]:
        s = shapes[0][2]
        crown = s.get("crown")
        return "rounded_punch", {"flat_radius": float(s["radius"]), "edge_radius": float(s["edge_radius"]),
                                 "crown": None if crown is None else float(crown)}, ""
    what = ", ".join(f"{n}.shape = {k!r}" for n, k, _ in shapes) or "two flat bodies"
    return None, {}, f"no analytic reference for this geometry ({what})"


def lateral_reference(inputs: dict, force: float, mu: float):
    """The analytic partial-slip loop matching the run's geometry, or why there is none.

    The reference needs smooth bodies (no roughness, texture or waviness), no adhesion or
    humidity, no normal-tangential coupling (Dundurs' beta = 0: identical materials, or an incompressible body on a rigid
    one) and a shape of :func:`reference_geometry`: a sphere gives Mindlin-Deresiewicz, a burl
    the rounded punch of Ciavarella and Jaeger
    (above).

    Parameters
    ----------
    inputs : dict
        The scenario echo (``summary["inputs"]``, SI numbers).
    force : float
        Normal force P (N), the repulsive force F0+ of the start.
    mu : float
        Friction coefficient.

    Returns
    -------
    (AxisymmetricPartialSlip or None, str)
        The reference (its ``name`` for tables and legends; the sphere's from the Hertz radius
        at ``force``) and an empty note, or None and a one-line note saying why.
    """
    from .mindlin import mindlin_compliance_k

    kind, par, note = reference_geometry(inputs)
    if kind is None:
        return None, note
    for name in ("body1", "body2"):
        b = (inputs or {}).get(name) or {}
        r = b.get("roughness") or {}
        if (isinstance(r, dict) and r.get("kind", "none") not in ("none", None)) or b.get("texture") or b.get("waviness"):
            return None, f"no analytic reference: {name} is rough, textured or wavy"
    if ((inputs or {}).get("adhesion") or {}).get("model") == "dugdale" or (inputs or {}).get("humidity"):
        # adhesive stresses or menisci add tension to the pressure the superposition differences
        return None, "no analytic reference: adhesion or menisci act on the contact"
    el = [_body_elastic((inputs or {}).get(n) or {}, n) for n in ("body1", "body2")]
    if None in el or force is None or not (float(force) > 0) or mu is None or not (float(mu) > 0):
        return None, "no analytic reference: moduli, normal force or friction coefficient unknown"
    (E1, n1), (E2, n2) = el
    k = mindlin_compliance_k(E1, n1, E2, n2)
    inv = [c for c, _ in _compliances(el)]  # 1/G
    beta = (1.0 - 2.0 * n1) * inv[0] - (1.0 - 2.0 * n2) * inv[1]
    if abs(beta) > 1e-6 * k:
        return None, ("no analytic reference: the dissimilar bodies couple the normal and tangential "
                      "tractions (Dundurs' beta != 0)")
    E_star = 1.0 / sum(0.0 if math.isinf(E) else (1.0 - nu * nu) / E for E, nu in el)
    if kind == "sphere":
        return sphere_partial_slip(force=force, mu=mu, k=k, E_star=E_star, radius=par["radius"]), ""
    return rounded_punch_partial_slip(force=force, mu=mu, k=k, E_star=E_star, **par), ""
