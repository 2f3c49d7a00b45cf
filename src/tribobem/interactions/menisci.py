"""Micro-meniscus islands at a rough interface with adsorbed water films (Paper B 2.2).

Paper B locates the areas that carry the capillary (Laplace) pressure in three steps
:

1. Cut the gap at the meniscus height (Paper B Eq. 9, with the films added)::

       S = |r_k| (cos theta1 + cos theta2) + e1 + e2

   with the LOCAL film thicknesses e1, e2 (the figure captions' "mean" is not what the text
   does) and ``|r_k|`` because the Kelvin radius is negative below saturation.  With zero
   contact angles the meniscus rises to ``2 |r_k|`` above the films.
2. Group the nodes with ``g < S`` into connected islands (:func:`scipy.ndimage.label`,
   4-connected by default; on a periodic grid an island that leaves one edge re-enters on
   the opposite one and is one island).
3. Keep the islands that hold a *seed*: a contact node, a wetted node (``g < e1 + e2``: the
   films touch) or a film-to-film air gap ``g - e1 - e2 < d_cr`` (the films jump into
   contact; Paper B takes d_cr as three water-molecule diameters, 0.84 nm).  The other
   islands are dry cross-cuts and carry nothing.

Limits, stated once here and tested:

* RH = 1 (``r_k = -inf``): the cut height is infinite, every node lies below it, and the
  whole grid is one island (one per grid-connected region), active when any seed exists.
  The capillary pressure is 0 at RH = 1 (:mod:`tribobem.interactions.water`), so the island
  then carries only the water-filled van der Waals term: the bodies are immersed.
* ``cos theta1 + cos theta2 = 0`` removes the meniscus term (S = e1 + e2, even at RH = 1);
  a negative sum with RH = 1 gives S = -inf (no island).  ``S <= 0`` anywhere means no
  island there: hydrophobic enough contact angles suppress the meniscus.
* A seed that lies above the cut height (possible when d_cr > |r_k| (cos theta1 + cos
  theta2), i.e. at low RH) belongs to no island and activates nothing: the meniscus it would
  nucleate is lower than its own gap.

Paper C scales the capillary pressure by a *contribution coefficient* that grows linearly
from 0 at 30 % RH (ice-like adsorbed water) to 1 at 60 % RH (bulk water; Asay and Kim
2005): :func:`contribution_coefficient`.  It multiplies the pressure only; the islands are
located as above.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.ndimage
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from ..errors import InputError

__all__ = ["Islands", "meniscus_islands", "cut_height", "contribution_coefficient", "CONTRIBUTION_KINDS",
           "CRITICAL_DISTANCE"]

#: Paper B's critical film-to-film distance: three water-molecule diameters (m).
CRITICAL_DISTANCE = 0.84e-9

#: Contribution-coefficient laws accepted by :func:`contribution_coefficient`.
CONTRIBUTION_KINDS = ("none", "linear_30_60")


@dataclass
class Islands:
    """Meniscus islands of one gap field.

    Attributes
    ----------
    labels : ndarray of int
        Island label per node (0: not below the cut height), consecutive from 1; periodic
        wrap-around already merged.
    active : ndarray of bool
        Nodes of the islands that hold a seed (they carry the capillary pressure when they
        are not in contact).
    count : int
        Number of islands (active or not).
    active_count : int
        Number of active islands.
    cut_height : ndarray
        The cut height S (m) per node (``inf`` at RH = 1).
    seeds : ndarray of bool
        Seed nodes: contact, wetted (g < e1 + e2) or film-to-film gap below d_cr.
    """

    labels: np.ndarray
    active: np.ndarray
    count: int
    active_count: int
    cut_height: np.ndarray
    seeds: np.ndarray

    @property
    def key(self) -> bytes:
        """A hashable digest of the active mask (used to detect cycles of the island fixed point)."""
        return np.packbits(self.active, axis=None).tobytes()


def _film(value, shape, name: str) -> np.ndarray:
    e = np.asarray(value, dtype=float)
    try:
        e = np.broadcast_to(e, shape)
    except ValueError:
        raise InputError(name, f"shape {e.shape} does not match the gap {shape} (give a scalar or a field)") from None
    if not np.all(np.isfinite(e)) or np.any(e < 0):
        raise InputError(name, "film thickness must be finite and >= 0 m everywhere")
    return e


def _kelvin(kelvin_radius) -> float:
    try:
        rk = float(kelvin_radius)
    except (TypeError, ValueError):
        raise InputError("kelvin_radius", f"must be a number (m), got {kelvin_radius!r}") from None
    if math.isnan(rk) or rk >= 0:
        raise InputError("kelvin_radius", f"must be < 0 m (RH < 1) or -inf (RH = 1), got {kelvin_radius!r}; "
                                          "the Kelvin radius r_k = gamma V/(R_g T ln RH) is negative below saturation")
    return rk


def _angles(contact_angles) -> tuple[float, float]:
    try:
        t1, t2 = (float(t) for t in contact_angles)
    except (TypeError, ValueError):
        raise InputError("contact_angles", f"give two angles in radians, got {contact_angles!r}") from None
    for name, t in (("contact_angles[0]", t1), ("contact_angles[1]", t2)):
        if not (0.0 <= t <= math.pi):
            raise InputError(name, f"contact angle must be in [0, pi] rad, got {t!r} (the scenario file takes degrees)")
    return t1, t2


def cut_height(film1, film2, kelvin_radius: float, contact_angles=(0.0, 0.0)):
    """The meniscus cut height S = |r_k| (cos theta1 + cos theta2) + e1 + e2 (m).

    Parameters
    ----------
    film1, film2 : float or ndarray
        Local film thicknesses e1, e2 on bodies 1 and 2 (m, >= 0).
    kelvin_radius : float
        r_k (m, < 0; ``-inf`` at RH = 1).
    contact_angles : (float, float)
        theta1, theta2 (radians, in [0, pi]).

    Returns
    -------
    float or ndarray
        S (m); ``+inf`` at RH = 1 with a positive cosine sum.
    """
    rk = _kelvin(kelvin_radius)
    t1, t2 = _angles(contact_angles)
    c = math.cos(t1) + math.cos(t2)
    if abs(c) < 1e-15:
        meniscus = 0.0  # no meniscus term (avoid inf * 0 at RH = 1)
    else:
        meniscus = abs(rk) * c
    return meniscus + np.asarray(film1, dtype=float) + np.asarray(film2, dtype=float)


def _merge_periodic(labels: np.ndarray, n: int, connectivity: int) -> tuple[np.ndarray, int]:
    """Merge labels that touch across opposite edges; relabel consecutively from 1."""
    if n == 0:
        return labels, 0
    a_parts, b_parts = [], []
    first, last = labels[0, :], labels[-1, :]
    pairs = [(first, last)]
    left, right = labels[:, 0], labels[:, -1]
    pairs.append((left, right))
    if connectivity == 8:
        # Diagonal neighbours across an edge (and the corners, through the rolls).
        pairs += [(first, np.roll(last, 1)), (first, np.roll(last, -1)),
                  (left, np.roll(right, 1)), (left, np.roll(right, -1))]
    for a, b in pairs:
        both = (a > 0) & (b > 0)
        a_parts.append(a[both])
        b_parts.append(b[both])
    a = np.concatenate(a_parts)
    b = np.concatenate(b_parts)
    if a.size == 0:
        return labels, n
    graph = coo_matrix((np.ones(a.size), (a, b)), shape=(n + 1, n + 1))
    _, comp = connected_components(graph, directed=False)
    # Components of labels 1..n, renumbered consecutively from 1 (label 0 stays 0).
    used = comp[1:]
    uniq, new = np.unique(used, return_inverse=True)
    lut = np.zeros(n + 1, dtype=labels.dtype)
    lut[1:] = new + 1
    return lut[labels], int(uniq.size)


def meniscus_islands(gap, film1, film2, kelvin_radius: float, contact, *, contact_angles=(0.0, 0.0),
                     critical_distance: float = CRITICAL_DISTANCE, periodic: bool = True,
                     connectivity: int = 4) -> Islands:
    """Locate the meniscus islands of a gap field (Paper B 2.2).

    Parameters
    ----------
    gap : array_like, shape (nx, ny)
        Gap g between the two solid surfaces (m); contact nodes have g <= 0.
    film1, film2 : float or array_like
        Adsorbed film thicknesses e1 (body 1) and e2 (body 2), m, >= 0, scalar or per node.
    kelvin_radius : float
        Kelvin radius r_k (m): negative below saturation, ``-inf`` at RH = 1.
    contact : array_like of bool or None
        Contact nodes (seeds).  None: the nodes with g <= 0.
    contact_angles : (float, float)
        theta1, theta2 in radians (default 0, 0: the meniscus rises to 2 |r_k|).
    critical_distance : float
        d_cr (m, >= 0): a film-to-film air gap below it seeds a meniscus (default 0.84 nm,
        three water-molecule diameters).
    periodic : bool
        Merge islands across opposite edges (periodic grid).
    connectivity : {4, 8}
        Neighbourhood of the labelling.

    Returns
    -------
    Islands

    Raises
    ------
    InputError
        Wrong shapes, NaN in the gap, negative films, r_k >= 0, contact angles outside
        [0, pi], negative d_cr, connectivity other than 4 or 8.
    """
    g = np.asarray(gap, dtype=float)
    if g.ndim != 2:
        raise InputError("gap", f"must be a 2-D field, got shape {g.shape}")
    if np.any(np.isnan(g)):
        raise InputError("gap", "contains NaN")
    e1 = _film(film1, g.shape, "film1")
    e2 = _film(film2, g.shape, "film2")
    if connectivity not in (4, 8):
        raise InputError("connectivity", f"must be 4 or 8, got {connectivity!r}")
    if not (math.isfinite(critical_distance) and critical_distance >= 0):
        raise InputError("critical_distance", f"must be a finite value >= 0 m, got {critical_distance!r}")
    if contact is None:
        cmask = g <= 0
    else:
        cmask = np.asarray(contact, dtype=bool)
        if cmask.shape != g.shape:
            raise InputError("contact", f"shape {cmask.shape} does not match the gap {g.shape}")

    S = np.broadcast_to(cut_height(e1, e2, kelvin_radius, contact_angles), g.shape)
    below = (g < S) | cmask
    below &= S > 0  # no meniscus where the cut height is not positive
    structure = scipy.ndimage.generate_binary_structure(2, 1 if connectivity == 4 else 2)
    labels, n = scipy.ndimage.label(below, structure=structure)
    if periodic:
        labels, n = _merge_periodic(labels, n, connectivity)

    films = e1 + e2
    seeds = cmask | (g < films) | (g - films < critical_distance)
    flag = np.zeros(n + 1, dtype=bool)
    flag[labels[seeds]] = True
    flag[0] = False
    active = flag[labels]
    return Islands(labels=labels, active=active, count=int(n), active_count=int(np.count_nonzero(flag)),
                   cut_height=np.array(S), seeds=seeds)


def contribution_coefficient(rh, kind: str = "linear_30_60"):
    """Paper C's contribution coefficient of the capillary pressure.

    Asay and Kim (2005) found the adsorbed water on SiO2 ice-like up to 30 % RH and bulk
    above 60 %; Paper C scales the capillary pressure by a coefficient that grows linearly
    between the two (0.17 at its 35 % RH).  Multiply the capillary pressure by it (the
    meniscus islands are located as without it).

    Parameters
    ----------
    rh : float or array_like
        Relative humidity, a fraction in (0, 1].
    kind : {"linear_30_60", "none"}
        ``"linear_30_60"``: clip((RH - 0.3) / 0.3, 0, 1); ``"none"``: 1 (full pressure).

    Returns
    -------
    float or ndarray
        The coefficient, in [0, 1].

    Raises
    ------
    InputError
        RH outside (0, 1] or an unknown ``kind``.
    """
    arr = np.asarray(rh, dtype=float)
    if arr.size == 0 or np.any(~np.isfinite(arr) | (arr <= 0) | (arr > 1)):
        raise InputError("humidity.rh", f"relative humidity must be a fraction in (0, 1], got {rh!r}")
    if kind == "none":
        out = np.ones_like(arr)
    elif kind == "linear_30_60":
        out = np.clip((arr - 0.3) / 0.3, 0.0, 1.0)
    else:
        raise InputError("humidity.contribution", f"unknown kind {kind!r}; choose among {', '.join(CONTRIBUTION_KINDS)}")
    return float(out) if out.ndim == 0 else out
