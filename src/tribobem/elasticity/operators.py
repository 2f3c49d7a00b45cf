"""Elastic integral operators: surface tractions -> surface displacements.

Two operators (SPEC 2), both convolutions evaluated with real FFTs and cached kernel
spectra:

* :func:`free_boundary_operator` -- DC-FFT (Liu, Wang & Liu 2000): the closed-form Love
  influence coefficients are laid out on a 2nx x 2ny wrap-around grid and the tractions are
  zero-padded to that size, so the cyclic convolution equals the linear one on the nx x ny
  domain (no periodic images).  For isolated contacts and non-periodic measured scans.
* :func:`periodic_operator` -- one cell of a periodic surface.  Default ``kernel="spectral"``:
  the continuous half-space kernel 2/(E* |q|) sampled at the DFT wavevectors (what Tamaas
  uses).  ``kernel="influence"``: the DFT of the *periodised* Love influence coefficients,
  computed exactly in Fourier space by Poisson summation over aliases,
  K_d(q) = sum_n 2/(E*|q_n|) sinc(q_n,x dx/2) sinc(q_n,y dy/2), q_n = q + 2 pi n/d,
  truncated at |n_x|, |n_y| <= ``n_alias``.  Both agree at wavelengths >> dx and differ near
  the Nyquist wavelength (tested).  The q = 0 mode is set to 0 in both: in a periodic system
  the mean displacement is arbitrary and is carried by the rigid approach instead.

Operators are shaped for several traction components (``components=("x", "y", "z")`` for the
coupled normal-tangential problem of dissimilar bodies).  Callers that need only the normal
part use :meth:`ConvolutionOperator.block` (``op.normal``), which is what the normal solvers
take; the coupled 3x3 operator therefore plugs in without changing them.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache
from typing import Mapping

import numpy as np

from ..grid import Grid
from ..materials import ContactPair
from .backend import Backend, get_backend
from .influence import composite_coefficients

AXES = ("x", "y", "z")


@dataclass(eq=False)
class ConvolutionOperator:
    """A (block) convolution operator on a grid.

    Parameters
    ----------
    grid : Grid
        The domain; displacements and tractions have shape ``grid.shape``.
    pair : ContactPair
        The two bodies (their composite compliances define the kernels).
    components : tuple of str
        Traction / displacement components, a subset of ("x", "y", "z").
    spectra : mapping
        ``spectra[out + in]`` is the rfft2 of the kernel giving u_out from traction_in, on
        ``fft_shape``.  Missing blocks are zero.
    fft_shape : tuple of int
        ``grid.shape`` (periodic) or twice it (free boundary, zero padding).
    backend : Backend
        Array/FFT backend the spectra live on.
    kind : str
        Human-readable description (reports, ``repr``).
    """

    grid: Grid
    pair: ContactPair
    components: tuple[str, ...]
    spectra: Mapping[str, object]
    fft_shape: tuple[int, int]
    backend: Backend
    kind: str
    _blocks: dict = field(default_factory=dict, repr=False)

    @property
    def periodic(self) -> bool:
        return self.grid.periodic

    @property
    def xp(self):
        return self.backend.xp

    @property
    def effective_modulus(self) -> float:
        return self.pair.effective_modulus

    def block(self, out: str, inp: str) -> "ConvolutionOperator":
        """The single-component operator giving u_out from traction_in."""
        key = out + inp
        if key not in self._blocks:
            spec = {"zz": self.spectra[key]} if key in self.spectra else {}
            self._blocks[key] = ConvolutionOperator(
                self.grid, self.pair, ("z",), spec, self.fft_shape, self.backend, f"{self.kind} [{key}]"
            )
        return self._blocks[key]

    @property
    def normal(self) -> "ConvolutionOperator":
        """The normal block u_z from p (the operator the normal solvers use)."""
        return self if self.components == ("z",) else self.block("z", "z")

    def spectrum(self, out: str = "z", inp: str = "z"):
        return self.spectra.get(out + inp)

    def __call__(self, traction):
        return self.apply(traction)

    def apply(self, traction):
        """Displacements (m) from tractions (Pa).

        Parameters
        ----------
        traction : array
            Shape ``grid.shape`` for a single-component operator, else
            ``(len(components),) + grid.shape`` in the order of ``components``.

        Returns
        -------
        array
            Same shape as ``traction``.
        """
        be, nx, ny = self.backend, self.grid.nx, self.grid.ny
        if len(self.components) == 1:
            spec = self.spectra.get("zz")
            if spec is None:
                return self.xp.zeros_like(traction)
            T = be.rfft2(traction, s=self.fft_shape)
            T *= spec
            u = be.irfft2(T, s=self.fft_shape)
            return u if self.periodic else u[:nx, :ny]
        T = [be.rfft2(traction[k], s=self.fft_shape) for k in range(len(self.components))]
        out = self.xp.zeros_like(traction)
        for i, ci in enumerate(self.components):
            acc = None
            for k, ck in enumerate(self.components):
                spec = self.spectra.get(ci + ck)
                if spec is None:
                    continue
                term = T[k] * spec
                acc = term if acc is None else acc + term
            if acc is not None:
                u = be.irfft2(acc, s=self.fft_shape)
                out[i] = u if self.periodic else u[:nx, :ny]
        return out

    def __repr__(self) -> str:
        return f"ConvolutionOperator({self.kind}, grid={self.grid.nx}x{self.grid.ny}, components={self.components})"


def _realify(spec: np.ndarray) -> np.ndarray:
    """Drop an imaginary part that is round-off (even kernels have real spectra)."""
    if np.abs(spec.imag).max() <= 1e-12 * max(np.abs(spec.real).max(), 1e-300):
        return np.ascontiguousarray(spec.real)
    return spec


def _wrapped_offsets(n: int, d: float) -> np.ndarray:
    """Offsets of a 2n wrap-around layout: 0..n-1, (unused) n, -(n-1)..-1 (times d)."""
    i = np.arange(2 * n)
    off = np.where(i < n, i, i - 2 * n).astype(float) * d
    return off


@lru_cache(maxsize=8)
def _free_boundary_cached(grid: Grid, pair: ContactPair, components: tuple, backend_name: str):
    be = get_backend(backend_name)
    nx, ny, dx, dy = grid.nx, grid.ny, grid.dx, grid.dy
    X = _wrapped_offsets(nx, dx)[:, None]
    Y = _wrapped_offsets(ny, dy)[None, :]
    spectra = {}
    for out in components:
        for inp in components:
            key = out + inp
            coeff = composite_coefficients(key, pair, X, Y, dx, dy)
            coeff[nx, :] = 0.0  # offsets +-nx never occur in the linear convolution
            coeff[:, ny] = 0.0
            if not np.any(coeff):
                continue
            spectra[key] = be.asarray(_realify(np.fft.rfft2(coeff)))
    return spectra


def free_boundary_operator(grid: Grid, pair: ContactPair, components=("z",), backend: str | Backend = "numpy") -> ConvolutionOperator:
    """DC-FFT operator of a non-periodic (free-boundary) domain, zero-padded to 2nx x 2ny.

    Parameters
    ----------
    grid : Grid
        Domain (``grid.periodic`` is ignored: this operator is always non-periodic).
    pair : ContactPair
        Materials of the two bodies.
    components : tuple of str
        ("z",) for normal contact, ("x", "y", "z") for the coupled problem.
    backend : str or Backend
        "numpy" or "cupy".

    Returns
    -------
    ConvolutionOperator
    """
    be = backend if isinstance(backend, Backend) else get_backend(backend)
    components = tuple(components)
    _check_components(components)
    if grid.periodic:
        grid = Grid(grid.nx, grid.ny, grid.lx, grid.ly, False)
    grid.check_memory(n_components=len(components))  # before any large allocation
    spectra = _free_boundary_cached(grid, pair, components, be.name)
    return ConvolutionOperator(grid, pair, components, spectra, (2 * grid.nx, 2 * grid.ny), be, "free boundary (DC-FFT)")


def _wavevectors(grid: Grid):
    qx = 2.0 * np.pi * np.fft.fftfreq(grid.nx, grid.dx)[:, None]
    qy = 2.0 * np.pi * np.fft.rfftfreq(grid.ny, grid.dy)[None, :]
    return qx, qy


@lru_cache(maxsize=8)
def _periodic_cached(grid: Grid, pair: ContactPair, kernel: str, n_alias: int, backend_name: str):
    be = get_backend(backend_name)
    E = pair.effective_modulus
    qx, qy = _wavevectors(grid)
    if kernel == "spectral":
        q = np.hypot(qx, qy)
        with np.errstate(divide="ignore"):
            spec = 2.0 / (E * q)
        spec[0, 0] = 0.0
    elif kernel == "influence":
        spec = np.zeros(np.broadcast_shapes(qx.shape, qy.shape))
        gx, gy = 2.0 * np.pi / grid.dx, 2.0 * np.pi / grid.dy
        for mx in range(-n_alias, n_alias + 1):
            Qx = qx + mx * gx
            sx = np.sinc(Qx * grid.dx / (2.0 * np.pi))  # np.sinc(t) = sin(pi t)/(pi t)
            for my in range(-n_alias, n_alias + 1):
                Qy = qy + my * gy
                sy = np.sinc(Qy * grid.dy / (2.0 * np.pi))
                Q = np.hypot(Qx, Qy)
                with np.errstate(divide="ignore", invalid="ignore"):
                    term = np.where(Q > 0, 2.0 / (E * Q), 0.0) * sx * sy
                spec += term
        spec[0, 0] = 0.0
    else:
        from ..errors import InputError

        raise InputError("solver.kernel", f"must be 'spectral' or 'influence', got {kernel!r}")
    return {"zz": be.asarray(np.ascontiguousarray(spec))}


def periodic_operator(grid: Grid, pair: ContactPair, components=("z",), kernel: str = "spectral",
                      n_alias: int = 8, backend: str | Backend = "numpy") -> ConvolutionOperator:
    """Operator of one periodic cell (see module docstring for ``kernel``).

    Parameters
    ----------
    grid : Grid
        The periodic cell.
    pair : ContactPair
        Materials.
    components : tuple of str
        Only ("z",) is available for the periodic operator so far.
    kernel : {"spectral", "influence"}
        Continuous kernel 2/(E*|q|), or the exact DFT of periodised influence coefficients.
    n_alias : int
        Alias images per direction for ``kernel="influence"``.
    backend : str or Backend
    """
    be = backend if isinstance(backend, Backend) else get_backend(backend)
    components = tuple(components)
    _check_components(components)
    if components != ("z",):
        raise NotImplementedError("the periodic operator supports the normal component only; "
                                  "use free_boundary_operator for coupled normal-tangential problems")
    if not grid.periodic:
        grid = Grid(grid.nx, grid.ny, grid.lx, grid.ly, True)
    grid.check_memory()  # before any large allocation
    spectra = _periodic_cached(grid, pair, kernel, n_alias, be.name)
    return ConvolutionOperator(grid, pair, components, spectra, grid.shape, be, f"periodic ({kernel})")


def make_operator(grid: Grid, pair: ContactPair, components=("z",), backend: str | Backend = "numpy", **kw) -> ConvolutionOperator:
    """The periodic or free-boundary operator, as ``grid.periodic`` says."""
    if grid.periodic:
        return periodic_operator(grid, pair, components, backend=backend, **kw)
    return free_boundary_operator(grid, pair, components, backend=backend)


def _check_components(components: tuple) -> None:
    if not components or any(c not in AXES for c in components) or len(set(components)) != len(components):
        raise ValueError(f"components must be distinct axes among {AXES}, got {components!r}")
