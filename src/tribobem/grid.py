"""The computational grid: nx x ny cells of size dx x dy, fields indexed ``[ix, iy]``."""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from .errors import InputError, MemoryBudgetError

#: Fraction of the available memory a single solve may plan to use.
MEMORY_FRACTION = 0.8


def available_memory() -> int:
    """Bytes of memory available to this process (falls back to 8 GiB if unknown).

    Returns
    -------
    int
        Available memory in bytes: psutil's ``available``, else the available physical pages,
        else 8 GiB.
    """
    try:
        import psutil

        return int(psutil.virtual_memory().available)
    except Exception:  # pragma: no cover - psutil is a dask dependency, normally present
        try:
            return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_AVPHYS_PAGES")  # noqa: F821
        except Exception:
            return 8 << 30


@dataclass(frozen=True)
class Grid:
    """A regular grid of cell centres.

    Parameters
    ----------
    nx, ny : int
        Number of cells along x and y.
    lx, ly : float
        Side lengths in m.
    periodic : bool
        True: the domain is one cell of a periodic surface (spectral operator).
        False: free boundary (zero-padded DC-FFT operator).

    Notes
    -----
    Cell centres are at ``x_i = (i + 1/2) dx - lx/2`` so the domain is centred on 0; a
    sphere generated on the grid is centred between the four middle cells for even n.
    """

    nx: int
    ny: int
    lx: float
    ly: float
    periodic: bool = False

    def __post_init__(self):
        for name, n in (("grid.nx", self.nx), ("grid.ny", self.ny)):
            if not isinstance(n, (int, np.integer)) or n < 2:
                raise InputError(name, f"number of cells must be an integer >= 2, got {n!r}")
        for name, length in (("grid.lx", self.lx), ("grid.ly", self.ly)):
            if not (isinstance(length, (int, float)) and math.isfinite(length) and length > 0):
                raise InputError(name, f"side length must be a finite value > 0 m, got {length!r}")

    @classmethod
    def square(cls, n: int, size: float, periodic: bool = False) -> "Grid":
        """An n x n grid of side ``size`` (m).

        Parameters
        ----------
        n : int
            Number of cells along x and y.
        size : float
            Side length (m).
        periodic : bool
            See :class:`Grid`.

        Returns
        -------
        Grid
        """
        return cls(n, n, size, size, periodic)

    @property
    def shape(self) -> tuple[int, int]:
        """(nx, ny): the shape of every field on the grid."""
        return (self.nx, self.ny)

    @property
    def dx(self) -> float:
        """Cell size along x, lx / nx (m)."""
        return self.lx / self.nx

    @property
    def dy(self) -> float:
        """Cell size along y, ly / ny (m)."""
        return self.ly / self.ny

    @property
    def cell_area(self) -> float:
        """dx * dy in m^2."""
        return self.dx * self.dy

    @property
    def area(self) -> float:
        """Nominal area lx * ly in m^2."""
        return self.lx * self.ly

    @cached_property
    def x(self) -> np.ndarray:
        """Cell-centre x coordinates (m), shape (nx,)."""
        return (np.arange(self.nx) + 0.5) * self.dx - 0.5 * self.lx

    @cached_property
    def y(self) -> np.ndarray:
        """Cell-centre y coordinates (m), shape (ny,)."""
        return (np.arange(self.ny) + 0.5) * self.dy - 0.5 * self.ly

    def meshgrid(self) -> tuple[np.ndarray, np.ndarray]:
        """X, Y arrays of shape (nx, ny) (``indexing='ij'``)."""
        return np.meshgrid(self.x, self.y, indexing="ij")

    def radius(self) -> np.ndarray:
        """Distance of every cell centre from the domain centre (m)."""
        X, Y = self.meshgrid()
        return np.hypot(X, Y)

    def translate(self, field, offset) -> np.ndarray:
        """A field on this grid moved rigidly by ``offset`` = (dx, dy) in m.

        Exact (a Fourier phase shift) on a periodic grid; cubic interpolation on a free-boundary
        grid, values beyond the edge repeating the edge.  Used for a counterface (its geometry and
        its water film) that translates under gross sliding.

        Parameters
        ----------
        field : array_like, shape ``self.shape``
            The values on the grid (any unit).
        offset : (float, float)
            Rigid displacement (m).

        Returns
        -------
        ndarray, shape ``self.shape``
            The moved field (a copy; the input itself when the offset is zero).
        """
        a = np.asarray(field, dtype=float)
        ox, oy = (float(v) for v in offset)
        if ox == 0.0 and oy == 0.0:
            return a
        if self.periodic:
            kx = 2.0 * np.pi * np.fft.fftfreq(self.nx, self.dx)[:, None]
            ky = 2.0 * np.pi * np.fft.rfftfreq(self.ny, self.dy)[None, :]
            return np.fft.irfft2(np.fft.rfft2(a) * np.exp(-1j * (kx * ox + ky * oy)), s=a.shape)
        from scipy.ndimage import shift

        return shift(a, (ox / self.dx, oy / self.dy), order=3, mode="nearest")

    def estimate_bytes(self, n_fields: int = 12, n_components: int = 1) -> int:
        """Rough peak memory (bytes) of a solve on this grid.

        ``n_fields`` full-size float64 work arrays plus the cached kernel spectra and FFT
        buffers (on the padded 2nx x 2ny grid for the free-boundary operator).

        Parameters
        ----------
        n_fields : int
            Number of full-size float64 work arrays per component.
        n_components : int
            Traction components solved together (1 normal, 2 tangential, 3 coupled); the
            kernel spectra grow with its square.

        Returns
        -------
        int
            Estimated peak memory (bytes).
        """
        # per grid node: the spectra of the c^2 blocks (real, N1 x (N2/2 + 1) doubles: 16 bytes
        # on the padded free-boundary grid, 4 on a periodic one) and the transforms' work arrays:
        # one component transforms in blocks (a half-spectrum of the unpadded rows, 16 bytes, or
        # 8 periodic, and its rows buffer), several hold a padded spectrum each plus their sum
        # (32 bytes each, 8 periodic).  Measured peaks (benchmarks/peers.py): 116 bytes per node
        # for a whole-grid 2048^2 free-boundary NormCG solve, 46-49 for a candidate-set one.
        c = n_components
        cells = self.nx * self.ny
        spec = 4 if self.periodic else 16
        work = (16 if self.periodic else 32) if c == 1 else (c + 1) * (8 if self.periodic else 32)
        per_node = n_fields * 8 * c + c * c * spec + work
        return int(per_node * cells)

    def check_memory(self, n_fields: int = 12, n_components: int = 1, budget: int | None = None) -> None:
        """Raise :class:`MemoryBudgetError` if a solve would not fit in memory.

        The estimate is checked before allocating, so that a too-large grid fails at once with
        a message instead of swapping or being killed.

        Parameters
        ----------
        n_fields, n_components : int
            As for :meth:`estimate_bytes`.
        budget : int, optional
            Memory (bytes) to plan against; default :func:`available_memory`.  Only
            :data:`MEMORY_FRACTION` of it may be used.

        Raises
        ------
        MemoryBudgetError
            The estimate exceeds the usable memory.
        """
        need = self.estimate_bytes(n_fields, n_components)
        have = int((budget if budget is not None else available_memory()) * MEMORY_FRACTION)
        if need > have:
            # memory grows with the number of cells: the largest square grid of this kind that fits
            fit = int(math.sqrt(self.nx * self.ny * have / need))
            raise MemoryBudgetError(
                f"grid.n: a {self.nx} x {self.ny} grid ({'periodic' if self.periodic else 'free boundary'}) "
                f"needs about {need / 2**30:.1f} GiB but only {have / 2**30:.1f} GiB of this machine's memory may "
                f"be used; reduce grid.n (about {fit} x {fit} fits here)"
            )
