"""Elastic integral operators: surface tractions -> surface displacements.

Two operators, both convolutions evaluated with real FFTs and cached kernel
spectra:

* :func:`free_boundary_operator` -- DC-FFT (Liu, Wang & Liu 2000): the closed-form Love
  influence coefficients are laid out on a 2nx x 2ny wrap-around grid and the tractions are
  zero-padded to that size, so the cyclic convolution equals the linear one on the nx x ny
  domain (no periodic images).  For isolated contacts and non-periodic measured scans.
* :func:`periodic_operator` -- one cell of a periodic surface.  Default ``kernel="spectral"``:
  the continuous Boussinesq-Cerruti half-space kernels sampled at the DFT wavevectors (for the
  normal block 2/(E* |q|), what Tamaas uses; the full 3x3 set is listed in
  :func:`periodic_operator`).  ``kernel="influence"``: the DFT of the *periodised* Love
  influence coefficients, computed exactly in Fourier space by Poisson summation over
  aliases, K_d(q) = sum_n K(q_n) sinc(q_n,x dx/2) sinc(q_n,y dy/2), q_n = q + 2 pi n/d,
  truncated at |n_x|, |n_y| <= ``n_alias`` (for the normal block K = 2/(E*|q|)).  Both agree
  at wavelengths >> dx and differ near the Nyquist wavelength (tested).  The q = 0 mode of
  every block is set to 0 in both: in a periodic system the mean displacement is arbitrary
  and is carried by the rigid approach (and tangential shifts) instead.

The kernels come from the pair's body model (``pair.model``, read by
:func:`tribobem.elasticity.bodies.body_model_of`; the homogeneous half-space described here
unless the pair names another): its periodic spectra, and its free-boundary influence
coefficients, which the DC-FFT code below lays out and transforms whatever the model.

Both operators take several traction components (``components=("x", "y", "z")`` for the
coupled normal-tangential problem of dissimilar bodies; component keys ``out + in``, e.g.
``"zx"`` is u_z from q_x).  The normal and in-plane blocks of the two bodies add, the
normal-tangential coupling blocks subtract (body 1 minus body 2).  The periodic coupling
blocks are purely imaginary (odd kernels), so their spectra are complex.  Units: tractions
in Pa, displacements in m.  Callers that need only the normal part use
:meth:`ConvolutionOperator.block` (``op.normal``), which is what the normal solvers take; the
coupled 3x3 operator therefore plugs in without changing them.
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Mapping

import numpy as np
import scipy.fft as sfft

from ..errors import InputError
from ..grid import Grid
from ..materials import ContactPair
from .backend import Backend, default_workers, single_spectrum, times_spectrum, work_buffers
from .backends import get_backend
from .bodies import body_model_of
from .cache import OperatorCache
from .malloc import lean_allocator

AXES = ("x", "y", "z")


@dataclass(eq=False)
class ConvolutionOperator:
    """A (block) convolution operator on a grid.

    Parameters
    ----------
    grid : Grid
        The domain; displacements and tractions have shape ``grid.shape``.
    pair : ContactPair
        The two bodies (their body model, ``pair.model``, made the kernels).
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
    reciprocal : bool
        Single-component operators only: divide by the spectrum instead of multiplying (the
        convolution with spectrum 1/K, e.g. NormCG's preconditioner, sharing K's array).

    Attributes
    ----------
    cache : OperatorCache
        What the solvers derive from this operator once (its blocks, preconditioners, kernel
        columns, work arrays); made empty with the operator (not a constructor argument), see
        :mod:`tribobem.elasticity.cache`.
    """

    grid: Grid
    pair: ContactPair
    components: tuple[str, ...]
    spectra: Mapping[str, object]
    fft_shape: tuple[int, int]
    backend: Backend
    kind: str
    reciprocal: bool = False
    # not an __init__ argument: a copy (dataclasses.replace) starts with its own empty cache
    cache: OperatorCache = field(default_factory=OperatorCache, init=False, repr=False)

    @property
    def periodic(self) -> bool:
        """Whether the grid is periodic (spectral operator) rather than free-boundary (DC-FFT)."""
        return self.grid.periodic

    @property
    def xp(self):
        """The array module of the backend (:mod:`numpy` or :mod:`cupy`)."""
        return self.backend.xp

    @property
    def effective_modulus(self) -> float:
        """The pair's effective modulus E* (Pa)."""
        return self.pair.effective_modulus

    @property
    def body_model(self):
        """The pair's body model (:mod:`tribobem.elasticity.bodies`), which made the spectra: what
        the solvers and checks ask for the bodies' response instead of computing it from E*."""
        return body_model_of(self.pair)

    def block(self, out: str, inp: str) -> "ConvolutionOperator":
        """The single-component operator giving u_out from traction_in.

        Parameters
        ----------
        out, inp : {"x", "y", "z"}
            Displacement and traction components.

        Returns
        -------
        ConvolutionOperator
            A ``("z",)``-component operator (the single-component convention the normal solvers
            take) whose only spectrum is the ``out + inp`` block; no spectrum when the block is
            zero.  Cached on this operator (``cache.blocks``).
        """
        key = out + inp
        blocks = self.cache.blocks
        if key not in blocks:
            spec = {"zz": self.spectra[key]} if key in self.spectra else {}
            blocks[key] = ConvolutionOperator(
                self.grid, self.pair, ("z",), spec, self.fft_shape, self.backend, f"{self.kind} [{key}]"
            )
        return blocks[key]

    @property
    def normal(self) -> "ConvolutionOperator":
        """The normal block u_z from p (the operator the normal solvers use)."""
        return self if self.components == ("z",) else self.block("z", "z")

    def spectrum(self, out: str = "z", inp: str = "z"):
        """The rfft2 kernel spectrum of block ``out + inp`` (m/Pa, on ``fft_shape``); None if zero.

        Parameters
        ----------
        out, inp : {"x", "y", "z"}
            Displacement and traction components.

        Returns
        -------
        array or None
            Complex or real spectrum of shape (N1, N2 // 2 + 1) on the backend; None for a zero
            block (the solvers then skip its convolution).
        """
        return self.spectra.get(out + inp)

    def __call__(self, traction):
        """Same as :meth:`apply`: displacements (m) from tractions (Pa).

        Parameters
        ----------
        traction : array
            Traction (Pa), shaped as :meth:`apply` says.

        Returns
        -------
        array
            Displacement (m), same shape as ``traction``.
        """
        return self.apply(traction)

    def apply(self, traction, out=None, single: bool = False):
        """Displacements (m) from tractions (Pa).

        Parameters
        ----------
        traction : array
            Shape ``grid.shape`` for a single-component operator, else
            ``(len(components),) + grid.shape`` in the order of ``components``.
        out : array, optional
            Single-component operator: a C-contiguous real array of ``grid.shape`` to write
            the displacement into (may be ``traction``); ignored otherwise.
        single : bool
            Single-component operator: transform in single precision (float32 / complex64
            transforms and a float32 copy of the spectrum; relative error ~1e-7 of the largest
            displacement), returning float32 when ``out`` is not given.  For the images of
            search directions and preconditioners, never for a residual that decides
            convergence.

        Returns
        -------
        array
            Same shape as ``traction`` (``out`` when given to a single-component operator).
        """
        if single and len(self.components) == 1:
            return self._apply_single(traction, out)
        be, nx, ny = self.backend, self.grid.nx, self.grid.ny
        # Free boundary with scipy.fft: the zero-padded transforms skip the padding rows
        # (Backend.rfft2_padded / irfft2_rows; the same arithmetic, tested).
        lean = not self.periodic and be._lean()
        fwd = (lambda a: be.rfft2_padded(a, self.fft_shape)) if lean else (lambda a: be.rfft2(a, s=self.fft_shape))
        if len(self.components) == 1:
            spec = self.spectra.get("zz")
            if spec is None:
                if out is None:
                    return self.xp.zeros_like(traction)
                out[...] = 0.0
                return out
            if lean and be.blocked(self.fft_shape):
                # Large free-boundary grids: in blocks, ~4 grid fields less at the peak.
                if out is None:
                    out = np.empty((nx, ny))
                return be.convolve_padded_blocked(np.asarray(traction, dtype=float), spec, self.fft_shape,
                                                  out=out, reciprocal=self.reciprocal)
            if lean:
                # The spectrum and the inverse's rows in reused (per-thread) arrays of the
                # backend, shared by every operator on it (the normal operator and its
                # preconditioner): no fresh multi-field arrays per call.
                N1, N2 = self.fft_shape
                shp = (N1, N2 // 2 + 1)
                bufs = work_buffers(be)
                T = bufs.get(("spectrum", shp))
                if T is None:
                    if len(bufs) > 16:
                        bufs.clear()
                    T = bufs[("spectrum", shp)] = np.empty(shp, dtype=complex)
                T = be.rfft2_padded(np.asarray(traction, dtype=float), self.fft_shape, out=T)
                times_spectrum(T, spec, self.reciprocal)
                rows = be.irfft2_rows(T, self.fft_shape, nx, out=be.rows_buffer(nx, ny, N2))
                if out is None:
                    return np.array(rows[:, :ny])
                out[...] = rows[:, :ny]
                return out
            T = fwd(traction)
            times_spectrum(T, spec, self.reciprocal)
            u = be.irfft2(T, s=self.fft_shape)
            u = u if self.periodic else u[:nx, :ny]
            if out is None:
                return u
            out[...] = u
            return out
        T = [fwd(traction[k]) for k in range(len(self.components))]
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
                if lean:
                    out[i] = be.irfft2_rows(acc, self.fft_shape, nx)[:, :ny]
                    continue
                u = be.irfft2(acc, s=self.fft_shape)
                out[i] = u if self.periodic else u[:nx, :ny]
        return out

    def _apply_single(self, traction, out=None):
        """:meth:`apply` of a single-component operator in single precision."""
        be, nx, ny, xp = self.backend, self.grid.nx, self.grid.ny, self.xp
        spec = self.spectra.get("zz")
        if spec is None:
            if out is None:
                return xp.zeros(self.grid.shape, dtype=np.float32)
            out[...] = 0.0
            return out
        spec = single_spectrum(self, ("zz", self.fft_shape), spec, keep_real=True)
        a = xp.asarray(traction, dtype=np.float32)
        lean = not self.periodic and be._lean()
        if lean and be.blocked(self.fft_shape):
            return be.convolve_padded_blocked(np.ascontiguousarray(a), spec, self.fft_shape, out=out,
                                              reciprocal=self.reciprocal, single=True)
        if lean:
            N1, N2 = self.fft_shape
            shp = (N1, N2 // 2 + 1)
            bufs = work_buffers(be)
            T = bufs.get(("spectrum", shp, "single"))
            if T is None:
                if len(bufs) > 16:
                    bufs.clear()
                T = bufs[("spectrum", shp, "single")] = np.empty(shp, dtype=np.complex64)
            T = be.rfft2_padded(a, self.fft_shape, out=T, single=True)
            times_spectrum(T, spec, self.reciprocal)
            rows = be.irfft2_rows(T, self.fft_shape, nx, out=be.rows_buffer(nx, ny, N2, dtype=np.float32))
        else:
            T = be.rfft2(a, s=self.fft_shape)
            if T.dtype != np.complex64:  # an engine without single-precision transforms
                T = T.astype(np.complex64)
            times_spectrum(T, spec, self.reciprocal)
            rows = be.irfft2(T, s=self.fft_shape)
        if out is None:
            return xp.array(rows[:nx, :ny], dtype=np.float32)
        out[...] = rows[:nx, :ny]
        return out

    def __repr__(self) -> str:
        return f"ConvolutionOperator({self.kind}, grid={self.grid.nx}x{self.grid.ny}, components={self.components})"


@lru_cache(maxsize=8)
def _free_boundary_cached(grid: Grid, pair: ContactPair, components: tuple, backend_name: str):
    be = get_backend(backend_name)
    spectra = {}
    for out in components:
        for inp in components:
            key = out + inp
            spec = _padded_kernel_spectrum(key, pair, grid.nx, grid.ny, grid.dx, grid.dy)
            if spec is not None:
                spectra[key] = be.asarray(spec)
    return spectra


#: Rows of the 2nx x 2ny coefficient array computed at a time (about 2^22 points per block).
_KERNEL_BLOCK_POINTS = 1 << 22
#: Blocks computed at once, at most (threads of the kernel build; its blocks shrink with them).
_KERNEL_THREADS = 8


def _row_blocks(nx: int, step: int):
    """Row ranges of the 2nx wrap-around layout (offsets 0..nx-1, -nx..-1), ``step`` rows at
    most, none across row nx (where the offsets jump from nx-1 to -nx), with the offset of
    their first row."""
    for lo, hi, k0 in ((0, nx, 0), (nx, 2 * nx, -nx)):
        for i0 in range(lo, hi, step):
            yield i0, min(hi, i0 + step), k0 + i0 - lo


def _padded_kernel_spectrum(key, pair, nx, ny, dx, dy):
    """The 2-D real FFT of the wrap-around coefficient array of block ``key`` (None if zero),
    real when its imaginary part is round-off.  The coefficients are the pair's body model's
    (:meth:`~tribobem.elasticity.bodies.BodyModel.influence_coefficients`; the half-space's from
    their corner lattice, :func:`~tribobem.elasticity.influence.lattice_coefficients`), transformed
    along y in blocks of rows, then along x in place, so that the peak is the complex
    half-spectrum and a few blocks, not several full 2nx x 2ny arrays (rfft along the last axis,
    then fft along the first: the transforms of ``rfft2``).  The blocks run on the FFT threads
    (at most ``_KERNEL_THREADS``): NumPy's ufuncs release the GIL, and each block writes its own
    rows, so the numbers do not depend on the thread count or the block size."""
    N1, N2 = 2 * nx, 2 * ny
    model = body_model_of(pair)
    C = np.empty((N1, N2 // 2 + 1), dtype=complex)
    threads = min(default_workers(), _KERNEL_THREADS)
    # the blocks in flight together hold about one single-threaded block (the peak stays C + one
    # block); a block's rows are computed alike whatever its size, so the numbers do not change
    step = max(1, max(_KERNEL_BLOCK_POINTS // threads, 1 << 18) // N2)
    # columns in natural order (offsets -ny..ny-1), rolled into the wrap-around order below
    yc = (np.arange(-ny, ny + 1) - 0.5) * dy

    def block(rows) -> bool:
        i0, i1, k0 = rows
        xc = (np.arange(k0, k0 + (i1 - i0) + 1) - 0.5) * dx
        coeff = model.influence_coefficients(pair, key, xc, yc)
        coeff[:, 0] = 0.0  # offset -ny (wrap-around column ny) never occurs in the linear convolution
        if i0 == nx:
            coeff[0, :] = 0.0  # nor offset -nx (row nx)
        coeff = np.roll(coeff, -ny, axis=1)
        C[i0:i1] = sfft.rfft(coeff, axis=1)
        return bool(np.any(coeff))

    blocks = list(_row_blocks(nx, step))
    threads = min(threads, len(blocks))
    if threads > 1:
        with ThreadPoolExecutor(max_workers=threads) as pool:
            nonzero = any(list(pool.map(block, blocks)))
    else:
        nonzero = any([block(b) for b in blocks])
    if not nonzero:
        return None
    # in place (scipy writes into C with overwrite_x: the half-spectrum is the peak), threaded
    C = sfft.fft(C, axis=0, overwrite_x=True, workers=default_workers())
    imag = real = 0.0
    for i0 in range(0, N1, step):
        blk = C[i0:i0 + step]
        imag = max(imag, float(np.abs(blk.imag).max()))
        real = max(real, float(np.abs(blk.real).max()))
    if imag <= 1e-12 * max(real, 1e-300):
        out = np.empty(C.shape)
        out[...] = C.real
        return out
    return C


def free_boundary_operator(grid: Grid, pair: ContactPair, components=("z",),
                           backend: str | Backend = "numpy") -> ConvolutionOperator:
    """DC-FFT operator of a non-periodic (free-boundary) domain, zero-padded to 2nx x 2ny.

    Parameters
    ----------
    grid : Grid
        Domain (``grid.periodic`` is ignored: this operator is always non-periodic).
    pair : ContactPair
        Materials of the two bodies; its body model (``pair.model``; None: the half-space) gives
        the kernels.
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
    if grid.nx * grid.ny >= LEAN_ALLOCATOR_NODES:
        lean_allocator()
    if grid.nx * grid.ny >= LAZY_SPECTRA_NODES:
        # large grids: the kernel spectra are made on first use (a candidate-set solve,
        # solvers.candidates, never needs the whole grid's 2nx x 2ny spectrum: its memory and its
        # build time); the model's coefficients of one cell now, so that a model without
        # free-boundary coefficients, or refusing this grid, says so here
        body_model_of(pair).influence_coefficients(pair, "zz", np.array([-0.5, 0.5]) * grid.dx,
                                                   np.array([-0.5, 0.5]) * grid.dy)
        spectra = LazySpectra(lambda: _free_boundary_cached(grid, pair, components, be.name))
    else:
        spectra = _free_boundary_cached(grid, pair, components, be.name)
    return ConvolutionOperator(grid, pair, components, spectra, (2 * grid.nx, 2 * grid.ny), be,
                               _kind("free boundary (DC-FFT)", pair))


class LazySpectra(Mapping):
    """The kernel spectra of an operator, made by ``make()`` on first access (a mapping).

    Parameters
    ----------
    make : callable
        Returns the ``{block: spectrum}`` dict (cached by its maker).
    """

    def __init__(self, make):
        self._make = make
        self._spectra = None

    @property
    def built(self) -> bool:
        """Whether the spectra have been made."""
        return self._spectra is not None

    def _get(self) -> dict:
        if self._spectra is None:
            self._spectra = self._make()
        return self._spectra

    def __getitem__(self, key):
        return self._get()[key]

    def __iter__(self):
        return iter(self._get())

    def __len__(self) -> int:
        return len(self._get())


#: Grids from this many nodes fix the allocator's mmap threshold (:mod:`.malloc`).
LEAN_ALLOCATOR_NODES = 1024 * 1024
#: Free-boundary grids from this many nodes make their kernel spectra on first use.
LAZY_SPECTRA_NODES = 512 * 512


@lru_cache(maxsize=8)
def _periodic_cached(grid: Grid, pair: ContactPair, components: tuple, kernel: str, n_alias: int, backend_name: str):
    be = get_backend(backend_name)
    if kernel not in ("spectral", "influence"):

        raise InputError("solver.kernel", f"must be 'spectral' or 'influence', got {kernel!r}")
    host = body_model_of(pair).periodic_spectra(pair, grid, components, kernel, n_alias)
    # onto the backend, a block that shares another's array (yx = xy) sharing it there too
    spectra, moved = {}, {}
    for k, a in host.items():
        if id(a) not in moved:
            moved[id(a)] = be.asarray(a)
        spectra[k] = moved[id(a)]
    return spectra


def periodic_operator(grid: Grid, pair: ContactPair, components=("z",), kernel: str = "spectral",
                      n_alias: int = 8, backend: str | Backend = "numpy") -> ConvolutionOperator:
    """Operator of one periodic cell: tractions (Pa) -> displacements (m).

    With the FFT convention of NumPy (forward transform ``sum_x f(x) exp(-i q.x)``) and
    ``q = (qx, qy)`` (rad/m), ``q = |q|``, one half-space (G, nu) has the Fourier kernels
    (m/Pa; rfft2(u) = K(q) rfft2(t), u in m, t in Pa)::

        zz = (1 - nu)/(G q)                   xx = [1/q - nu qx^2/q^3]/G
        yy = [1/q - nu qy^2/q^3]/G            xy = yx = -nu qx qy/(G q^3)
        zx = -xz = -i (1 - 2 nu) qx/(2 G q^2) zy = -yz = -i (1 - 2 nu) qy/(2 G q^2)

    (the transforms of the point kernels).  The two bodies' normal and in-plane
    kernels add (zz = 2/(E* q)); the coupling blocks subtract, body 1 minus body 2, and vanish
    for identical materials (they are then left out of ``spectra``, as xy/yx are when both
    nu are 0).  A rigid body adds 0.
    The q = 0 mode of every block is 0 (the mean displacement is carried by the rigid
    approach / shifts).  Blocks odd in qx (xy, zx, xz) or qy (xy, zy, yz) are 0 on the
    Nyquist row / column of an even grid, as the DFT of any odd periodic kernel is.

    Parameters
    ----------
    grid : Grid
        The periodic cell (a non-periodic grid is taken as periodic).
    pair : ContactPair
        Materials of the two bodies; its body model (``pair.model``; None: the half-space) gives
        the kernels.
    components : tuple of str
        ("z",) for normal contact (default); ("x", "y", "z") (or a subset) for the coupled
        normal-tangential problem.
    kernel : {"spectral", "influence"}
        "spectral": the continuous kernels above sampled at the DFT wavevectors.
        "influence": the exact DFT of the periodised piecewise-constant (Love) influence
        coefficients, by Poisson summation: each continuous kernel times
        sinc(Qx dx/2) sinc(Qy dy/2), summed over aliases Q = q + 2 pi (mx/dx, my/dy),
        |mx|, |my| <= ``n_alias``.
    n_alias : int
        Alias images per direction for ``kernel="influence"``.
    backend : str or Backend
        "numpy" or "cupy"; the spectra live there.

    Returns
    -------
    ConvolutionOperator
        Spectra (rfft2 layout, shape (nx, ny//2 + 1)) are cached per (grid, pair,
        components, kernel, n_alias, backend); the coupling blocks are complex (purely
        imaginary), the others real.
    """
    be = backend if isinstance(backend, Backend) else get_backend(backend)
    components = tuple(components)
    _check_components(components)
    if not grid.periodic:
        grid = Grid(grid.nx, grid.ny, grid.lx, grid.ly, True)
    grid.check_memory(n_components=len(components))  # before any large allocation
    if grid.nx * grid.ny >= LEAN_ALLOCATOR_NODES:
        lean_allocator()
    spectra = _periodic_cached(grid, pair, components, kernel, n_alias, be.name)
    return ConvolutionOperator(grid, pair, components, spectra, grid.shape, be, _kind(f"periodic ({kernel})", pair))


def make_operator(grid: Grid, pair: ContactPair, components=("z",), backend: str | Backend = "numpy",
                  **kw) -> ConvolutionOperator:
    """The periodic or free-boundary operator, as ``grid.periodic`` says.

    Parameters
    ----------
    grid : Grid
        The domain (sizes in m); ``grid.periodic`` picks the operator.
    pair : ContactPair
        The two bodies and their body model (``pair.model``; None: the half-space).
    components : tuple of str
        Traction / displacement components, a subset of ("x", "y", "z").
    backend : str or Backend
        "numpy" or "cupy"; the spectra live there.
    **kw
        Passed to :func:`periodic_operator` (``kernel``, ``n_alias``); ignored for the free
        boundary, which has one kernel only.

    Returns
    -------
    ConvolutionOperator
    """
    if grid.periodic:
        return periodic_operator(grid, pair, components, backend=backend, **kw)
    return free_boundary_operator(grid, pair, components, backend=backend)


def _kind(base: str, pair: ContactPair) -> str:
    """The operator's description: ``base``, with the body model's name unless it is the
    half-space (whose operators keep the descriptions they always had)."""
    name = body_model_of(pair).name
    return base if name == "halfspace" else f"{base}, {name} bodies"


def _check_components(components: tuple) -> None:
    if not components or any(c not in AXES for c in components) or len(set(components)) != len(components):
        raise ValueError(f"components must be distinct axes among {AXES}, got {components!r}")
