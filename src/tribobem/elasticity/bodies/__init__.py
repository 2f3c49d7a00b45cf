"""Elastic body models by name: what the operators, solvers and checks ask the bodies for.

:data:`BODY_MODELS` maps a name to a :class:`~.base.BodyModel` subclass; ``"halfspace"``
(:class:`~.halfspace.HalfSpace`, two homogeneous half-spaces) is the model of every
:class:`~tribobem.materials.ContactPair` that names none.  A layered or finite-thickness body is
one module: a subclass of :class:`~.base.BodyModel` registered with :func:`register_body_model`
and given to the pair (``ContactPair(body1, body2, model=...)``); :func:`body_model_of` is how
the operators and checks read it.
"""

from __future__ import annotations

from ...errors import InputError
from .base import BodyModel
from .halfspace import HalfSpace, halfspace_self_compliance
from .layered import CoatedHalfSpace

__all__ = ["BODY_MODELS", "BodyModel", "CoatedHalfSpace", "HalfSpace", "body_model", "body_model_of", "halfspace_self_compliance",
           "register_body_model", "unregister_body_model", "DEFAULT_BODY_MODEL"]

#: The registered body models, by name.
BODY_MODELS: dict[str, type[BodyModel]] = {"halfspace": HalfSpace, "coated": CoatedHalfSpace}

#: The model of a pair that names none.
DEFAULT_BODY_MODEL = HalfSpace()


def register_body_model(cls: type[BodyModel]) -> type[BodyModel]:
    """Register a body model under its ``name`` (usable as a class decorator).

    Parameters
    ----------
    cls : type
        A :class:`BodyModel` subclass with a non-empty ``name``.

    Returns
    -------
    type
        ``cls``.

    Raises
    ------
    ValueError
        Not a BodyModel subclass, no name, or the name taken by another class.
    """
    if not (isinstance(cls, type) and issubclass(cls, BodyModel)) or not cls.name:
        raise ValueError(f"a body model is a named BodyModel subclass, got {cls!r}")
    if BODY_MODELS.get(cls.name, cls) is not cls:
        raise ValueError(f"body model {cls.name!r} is already registered ({BODY_MODELS[cls.name]!r})")
    BODY_MODELS[cls.name] = cls
    return cls


def unregister_body_model(name: str) -> None:
    """Remove the body model ``name`` (tests that register their own); the half-space stays.

    Parameters
    ----------
    name : str
        A registered model's name other than ``"halfspace"``.
    """
    if name == "halfspace":
        raise ValueError("the half-space body model cannot be removed")
    BODY_MODELS.pop(name, None)


def body_model(name: str, **params) -> BodyModel:
    """The body model ``name`` with its parameters.

    Parameters
    ----------
    name : str
        A key of :data:`BODY_MODELS`.
    **params
        The model's own parameters (none for ``"halfspace"``).

    Returns
    -------
    BodyModel

    Raises
    ------
    InputError
        For a name that is not registered.
    """
    cls = BODY_MODELS.get(name)
    if cls is None:
        raise InputError("body_model", f"must be one of {', '.join(sorted(BODY_MODELS))}; got {name!r}")
    return cls(**params)


def body_model_of(pair) -> BodyModel:
    """The body model of a pair: its ``model``, or the half-space when it names none.

    Parameters
    ----------
    pair : ContactPair
        The two bodies.

    Returns
    -------
    BodyModel
        ``pair.model``, or :data:`DEFAULT_BODY_MODEL`.

    Raises
    ------
    InputError
        When ``pair.model`` is neither None nor a :class:`BodyModel`.
    """
    model = pair.model
    if model is None:
        return DEFAULT_BODY_MODEL
    if not isinstance(model, BodyModel):
        raise InputError("bodies.model", f"must be a BodyModel (tribobem.elasticity.bodies), got {model!r}")
    return model
