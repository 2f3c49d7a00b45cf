"""A testing backend with CuPy's host/device rules and NumPy underneath (no GPU needed).

``get_backend("strict")`` (or :func:`strict_backend`) returns a :class:`StrictBackend`: its
arrays are :class:`DeviceArray` objects, a NumPy array in a wrapper that is *not* an
``np.ndarray`` -- as a ``cupy.ndarray`` is not -- and that refuses what CuPy refuses:

* a host array (any ``np.ndarray``, 0-d included) as an operand of a ufunc, of an ``xp``
  function, of ``np.<function>(device, ...)`` (NEP 18 dispatch), or of an arithmetic operator
  with a device array: ``TypeError: Unsupported type <class 'numpy.ndarray'>``, CuPy's
  message.  Python and NumPy scalars (``float``, ``np.float64``, ...) are allowed, as in CuPy;
* implicit conversion to the host: ``np.asarray(dev)``, ``np.array(dev)``, a device array
  stored into a host array, a SciPy routine called on a device array:
  ``TypeError: Implicit conversion to a NumPy array is not allowed``, as in CuPy;
* a host array as an index of, or as a value assigned into, a device array.  Stricter than
  CuPy, which copies such an array to the device silently on every call (a hidden transfer,
  what a hot loop must not do).

Allowed, as on CuPy: ``float(dev)`` / ``bool(dev)`` / ``int(dev)`` of a one-element array
(an implicit synchronisation), ``xp.asarray(host)`` / ``Backend.asarray`` (the explicit
transfer; it copies), ``Backend.to_numpy(dev)`` / ``dev.get()`` (the explicit way back; a copy).
Reductions and scalar indexing give 0-d device arrays, not NumPy scalars, as in CuPy.

The backend is for tests (``tests/elasticity/test_device_clean.py`` runs every run kind on it): it makes
a host array reaching the device array module fail on a machine without a GPU, where the CuPy
backend cannot run.  Its results equal the NumPy backend's (same NumPy arithmetic, the FFTs of
the NumPy backend's engine).  It is slower than the NumPy backend (a Python wrapper per
operation).  The scenario schema does not offer it.
"""

from __future__ import annotations

import types
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numpy.lib.mixins import NDArrayOperatorsMixin

from .backend import Backend

__all__ = ["DeviceArray", "StrictBackend", "strict_backend", "strict_namespace", "COUNTS", "reset_counts"]

_SCALARS = (int, float, complex, bool, np.generic)

#: Explicit transfers and synchronisations since the last :func:`reset_counts` (diagnostics
#: of the tests: a hot loop should not grow them per iteration).  ``to_device``: host data
#: copied by ``xp.asarray`` / ``Backend.asarray``; ``to_host``: ``get`` / ``Backend.to_numpy``
#: of a device array; ``scalar``: ``float`` / ``int`` / ``bool`` of a device array.
COUNTS = {"to_device": 0, "to_host": 0, "scalar": 0}


def reset_counts() -> dict:
    """The counts so far (a copy), then zero them.

    Returns
    -------
    dict
        ``{"to_device": int, "to_host": int, "scalar": int}`` as they were before the reset.
    """
    out = dict(COUNTS)
    for k in COUNTS:
        COUNTS[k] = 0
    return out


_IMPLICIT = ("Implicit conversion to a NumPy array is not allowed (strict device backend, as CuPy). "
             "Please use Backend.to_numpy() to construct a NumPy array explicitly.")


def _unsupported(x, where: str) -> TypeError:
    return TypeError(f"Unsupported type {type(x)} ({where}: a host array met a device array; "
                     "move it with Backend.asarray or compute it with backend.xp)")


def _wrap(x):
    """NumPy results -> device: arrays and NumPy scalars become DeviceArray (scalars 0-d, as
    CuPy returns them); tuples and lists element-wise; anything else unchanged."""
    if isinstance(x, np.ndarray):
        return DeviceArray(x)
    if isinstance(x, np.generic):
        return DeviceArray(np.asarray(x))
    if isinstance(x, tuple):
        return tuple(_wrap(v) for v in x)
    if isinstance(x, list):
        return [_wrap(v) for v in x]
    return x


def _operand(x, where: str):
    """A ufunc operand: a device array or a scalar (CuPy's kernels take nothing else)."""
    if isinstance(x, DeviceArray):
        return x._a
    if isinstance(x, _SCALARS):
        return x
    raise _unsupported(x, where)


def _unwrap(x, where: str):
    """Arguments of an ``xp`` function: device arrays unwrapped (in lists, tuples and dicts
    too); a host array is refused; other objects (scalars, dtypes, shapes, callables) pass."""
    if isinstance(x, DeviceArray):
        return x._a
    if isinstance(x, np.ndarray):
        raise _unsupported(x, where)
    if isinstance(x, (tuple, list)):
        return type(x)(_unwrap(v, where) for v in x)
    if isinstance(x, dict):
        return {k: _unwrap(v, where) for k, v in x.items()}
    return x


def _index(idx, where: str):
    """An index of a device array: device index arrays unwrapped, host arrays refused."""
    if isinstance(idx, tuple):
        return tuple(_index(i, where) for i in idx)
    if isinstance(idx, DeviceArray):
        return idx._a
    if isinstance(idx, np.ndarray):
        raise _unsupported(idx, where + " (index)")
    if isinstance(idx, list):
        return _unwrap(idx, where + " (index)")
    return idx


def _apply_ufunc(ufunc, method: str, inputs, kwargs):
    where = f"{ufunc.__name__}.{method}" if method != "__call__" else ufunc.__name__
    if method == "at":  # ufunc.at(a, indices[, b]): the indices follow the indexing rules
        args = (_operand(inputs[0], where), _index(inputs[1], where)) + tuple(_operand(x, where) for x in inputs[2:])
    else:
        args = tuple(_operand(x, where) for x in inputs)
    out = kwargs.get("out")
    kw = dict(kwargs)
    if out is not None:
        outs = out if isinstance(out, tuple) else (out,)
        for o in outs:
            if o is not None and not isinstance(o, DeviceArray):
                raise _unsupported(o, where + " (out)")
        kw["out"] = tuple(o._a if o is not None else None for o in outs)
    if "where" in kw and not isinstance(kw["where"], bool):
        kw["where"] = _operand(kw["where"], where + " (where)")
    result = getattr(ufunc, method)(*args, **kw)
    if out is not None:  # the device arrays written into
        outs = out if isinstance(out, tuple) else (out,)
        return outs[0] if len(outs) == 1 else outs
    return _wrap(result)


class DeviceArray(NDArrayOperatorsMixin):
    """A 'device' array of the strict backend: a NumPy array behind CuPy's rules (see the
    module docstring).  Operators, ``np.<ufunc>`` and ``np.<function>`` on it dispatch to
    NumPy with every operand checked; attributes and methods are NumPy's, results wrapped.

    Parameters
    ----------
    a : numpy.ndarray
        The host array to hold (not copied); create device arrays through
        ``StrictBackend.asarray`` instead, which counts the transfer.

    Raises
    ------
    TypeError
        When ``a`` is not a NumPy array.
    """

    __slots__ = ("_a",)

    def __init__(self, a: np.ndarray):
        if not isinstance(a, np.ndarray):
            raise TypeError("DeviceArray wraps a NumPy array; use StrictBackend.asarray")
        object.__setattr__(self, "_a", a)

    # -- what CuPy refuses ------------------------------------------------------------

    def __array__(self, dtype=None, copy=None):
        raise TypeError(_IMPLICIT)

    def __array_ufunc__(self, ufunc, method, *inputs, **kwargs):
        return _apply_ufunc(ufunc, method, inputs, kwargs)

    def __array_function__(self, func, types_, args, kwargs):
        name = getattr(func, "__name__", str(func))
        return _wrap(func(*_unwrap(args, name), **_unwrap(kwargs, name)))

    # -- the explicit way back --------------------------------------------------------

    def get(self) -> np.ndarray:
        """A host copy (``cupy.ndarray.get``)."""
        COUNTS["to_host"] += 1
        return self._a.copy()

    # -- Python protocol --------------------------------------------------------------

    def __getitem__(self, idx):
        return _wrap(self._a[_index(idx, "__getitem__")])

    def __setitem__(self, idx, value):
        if isinstance(value, DeviceArray):
            value = value._a
        elif isinstance(value, np.ndarray):
            raise _unsupported(value, "__setitem__ (value)")
        elif isinstance(value, (list, tuple)):
            value = _unwrap(value, "__setitem__ (value)")
        self._a[_index(idx, "__setitem__")] = value

    def __setattr__(self, name, value):
        if name in ("shape", "dtype"):
            setattr(self._a, name, value)
            return
        raise AttributeError(f"cannot set {name!r} on a DeviceArray")

    def __getattr__(self, name):
        if name.startswith("__"):
            raise AttributeError(name)
        attr = getattr(self._a, name)
        if isinstance(attr, np.ndarray):  # T, real, imag: views, wrapped (writes go through)
            return DeviceArray(attr)
        if callable(attr):
            def method(*args, **kwargs):
                where = f"ndarray.{name}"
                return _wrap(attr(*_unwrap(args, where), **_unwrap(kwargs, where)))

            method.__name__ = name
            return method
        return attr

    def __len__(self):
        return len(self._a)

    def __iter__(self):
        for row in self._a:
            yield _wrap(row)

    def _one(self, kind: str):
        if self._a.size != 1:
            raise TypeError(f"only one-element device arrays can be converted to Python {kind}")
        COUNTS["scalar"] += 1
        return self._a.reshape(()).item()

    def __float__(self):
        return float(self._one("scalars"))

    def __int__(self):
        return int(self._one("scalars"))

    def __complex__(self):
        return complex(self._one("scalars"))

    def __bool__(self):
        return bool(self._one("bools"))

    def __copy__(self):
        return DeviceArray(self._a.copy())

    def __deepcopy__(self, memo):
        return DeviceArray(self._a.copy())

    def __format__(self, spec):
        return format(self._a.reshape(()).item() if self._a.ndim == 0 else self._a, spec)

    def __repr__(self):
        return "DeviceArray(" + repr(self._a)[len("array("):]

    def __str__(self):
        return str(self._a)

    __hash__ = None


class _StrictUfunc:
    """``xp.<ufunc>``: operands must be device arrays or scalars; results are device arrays."""

    def __init__(self, ufunc):
        self._ufunc = ufunc

    def __call__(self, *inputs, **kwargs):
        return _apply_ufunc(self._ufunc, "__call__", inputs, kwargs)

    def __getattr__(self, name):
        attr = getattr(self._ufunc, name)
        if name in ("reduce", "accumulate", "reduceat", "outer", "at"):
            return lambda *inputs, **kwargs: _apply_ufunc(self._ufunc, name, inputs, kwargs)
        return attr

    def __repr__(self):
        return f"<strict ufunc {self._ufunc.__name__!r}>"


#: ``xp`` functions that move host data to the device (CuPy's explicit transfers).
_TRANSFERS = frozenset({"asarray", "array", "asanyarray"})


def _deep_host(x):
    """Device arrays in (nested lists of) arguments of a transfer: their host values."""
    if isinstance(x, DeviceArray):
        return x._a
    if isinstance(x, (tuple, list)):
        return type(x)(_deep_host(v) for v in x)
    return x


def _strict_function(func, name: str):
    if name in _TRANSFERS:
        def transfer(obj, *args, **kwargs):
            if isinstance(obj, DeviceArray):
                kwargs.setdefault("copy", None if name != "array" else True)
                return DeviceArray(np.array(obj._a, *args, **kwargs))
            kwargs["copy"] = True  # host -> device is a copy: later host writes do not reach it
            COUNTS["to_device"] += 1
            return DeviceArray(np.array(_deep_host(obj), *args, **kwargs))

        transfer.__name__ = name
        return transfer

    def function(*args, **kwargs):
        return _wrap(func(*_unwrap(args, name), **_unwrap(kwargs, name)))

    function.__name__ = name
    function.__doc__ = getattr(func, "__doc__", None)
    return function


class _StrictNamespace:
    """``StrictBackend.xp``: NumPy's names behind CuPy's rules (sub-modules such as ``fft``
    and ``linalg`` alike); ``xp.ndarray`` is :class:`DeviceArray`."""

    def __init__(self, module):
        object.__setattr__(self, "_mod", module)
        object.__setattr__(self, "_names", {})
        # not NumPy's name: code that caches per array module (xp.__name__) keeps the two apart
        object.__setattr__(self, "__name__", "tribobem.strict." + module.__name__)

    def __getattr__(self, name):
        names = self._names
        if name in names:
            return names[name]
        if name == "ndarray":
            out = DeviceArray
        else:
            attr = getattr(self._mod, name)
            if isinstance(attr, types.ModuleType):
                out = _StrictNamespace(attr)
            elif isinstance(attr, np.ufunc):
                out = _StrictUfunc(attr)
            elif isinstance(attr, type) or not callable(attr):
                out = attr  # dtypes, errstate, finfo, constants
            else:
                out = _strict_function(attr, name)
        names[name] = out
        return out

    def __setattr__(self, name, value):
        raise AttributeError("the strict array namespace is read-only")

    def __repr__(self):
        return f"<strict device namespace over {self._mod.__name__}>"


@lru_cache(maxsize=None)
def strict_namespace() -> _StrictNamespace:
    """The strict ``xp`` (one per process).

    Returns
    -------
    _StrictNamespace
        A read-only module-like namespace over :mod:`numpy` whose functions check their
        operands and wrap their results in :class:`DeviceArray`.
    """
    return _StrictNamespace(np)


@dataclass(frozen=True)
class StrictBackend(Backend):
    """The NumPy backend's arithmetic and FFTs behind CuPy's host/device rules (module
    docstring).  ``name`` is ``"strict"``: the code paths are the non-NumPy (CuPy) ones.

    Its FFTs are pocketfft's (``scipy.fft``) whatever the engine: those of the NumPy backend's
    lean paths (free boundary, preconditioner boxes) with every engine, and of its whole-array
    ones (kernel spectra, periodic operators) with the ``scipy`` engine.  Its results equal a
    NumPy backend's on the ``scipy`` engine to round-off, as tests/elasticity/test_device_clean.py checks; on
    another engine the kernel spectra differ by round-off, which a multistable adhesive contact
    can carry to another branch.

    Attributes
    ----------
    name : str
        ``"strict"`` (any name but ``"numpy"`` takes the solvers' CuPy code paths, which is
        what this backend tests).
    """

    name: str = "strict"

    @property
    def xp(self):
        """The strict array namespace (:func:`strict_namespace`)."""
        return strict_namespace()

    def rfft2(self, a, s=None):
        """:meth:`Backend.rfft2` of a device array, by pocketfft (``scipy.fft``).

        Parameters
        ----------
        a : DeviceArray
            Real field.
        s : tuple of int, optional
            Transform grid; None: ``a.shape``.

        Returns
        -------
        DeviceArray
            The complex half spectrum.

        Raises
        ------
        TypeError
            When ``a`` is a host array (as CuPy's FFT refuses one).
        """
        if not isinstance(a, DeviceArray):
            raise _unsupported(a, "rfft2")
        return DeviceArray(_host_backend("scipy").rfft2(a._a, s=s))

    def irfft2(self, a, s):
        """:meth:`Backend.irfft2` of a device array, by pocketfft (``scipy.fft``).

        Parameters
        ----------
        a : DeviceArray
            Complex half spectrum.
        s : tuple of int
            The real grid.

        Returns
        -------
        DeviceArray
            The real field of shape ``s``.

        Raises
        ------
        TypeError
            When ``a`` is a host array.
        """
        if not isinstance(a, DeviceArray):
            raise _unsupported(a, "irfft2")
        return DeviceArray(_host_backend("scipy").irfft2(a._a, s=s))


@lru_cache(maxsize=None)
def _host_backend(fft: str) -> Backend:
    return Backend("numpy", fft=fft)


@lru_cache(maxsize=None)
def strict_backend() -> StrictBackend:
    """The strict testing backend (also ``get_backend("strict")``).

    Returns
    -------
    StrictBackend
        One instance per process (cached, so its FFT plans are made once).
    """
    return StrictBackend()
