"""Boundary conditions per tagged segment: displacement, traction, rigid loading block.

A component given as a number is uniform; a callable receives points (m, 2) and returns
(m,) values. ``None`` leaves the component to another condition (a segment component that
no condition names is traction free).
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Callable
from typing import Union

import attrs
import numpy as np

from .errors import InputError
from .validators import as_float, as_scalar, shown

Component = Union[float, Callable[[np.ndarray], np.ndarray], None]  # noqa: UP007


def _component(value, instance, attribute) -> Component:
    """A number (numpy's too, as a float; no True, no "3"), finite, or a callable, or None."""
    if value is None or callable(value):
        return value
    if type(value) is float and math.isfinite(value):
        return value  # the common case, without the number checks' ABC lookups
    value = as_scalar(value)
    where = f"{type(instance).__name__}.{attribute.name}"
    fix = "give a number, a function of the points (m, 2) -> (m,), or None to leave it free"
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise InputError(f"{where} must be a number, got {shown(value)}; {fix}")
    if not math.isfinite(as_float(value)):
        raise InputError(f"{where} must be finite, got {shown(value)}; {fix}")
    return float(value)


#: a component field: checked and stored as a float, a callable or None
_COMPONENT = attrs.Converter(_component, takes_self=True, takes_field=True)


def _force(value) -> tuple[float, float]:
    """The block's resultant (Fx, Fy): two finite numbers (no True, no "3")."""
    if (
        type(value) is tuple
        and len(value) == 2
        and all(type(v) is float and math.isfinite(v) for v in value)
    ):
        return (float(value[0]), float(value[1]))  # the common case, without ABC lookups
    fix = "give (Fx, Fy) in N/mm, e.g. (0.0, -100.0)"
    pair = tuple(value) if isinstance(value, (tuple, list, np.ndarray)) else None
    if pair is None or len(pair) != 2:
        raise InputError(f"LoadingBlock.force must be a pair (Fx, Fy), got {value!r}; {fix}")
    pair = tuple(as_scalar(v) for v in pair)
    for name, v in zip(("Fx", "Fy"), pair, strict=True):
        if isinstance(v, (bool, np.bool_)) or not isinstance(v, numbers.Real):
            raise InputError(f"LoadingBlock.force {name} must be a number, got {shown(v)}; {fix}")
        if not math.isfinite(as_float(v)):
            raise InputError(f"LoadingBlock.force {name} must be finite, got {shown(v)}; {fix}")
    return tuple(float(v) for v in pair)


def evaluate(component: Component, points: np.ndarray) -> np.ndarray:
    """Values of a component at ``points``, checked finite."""
    if callable(component):
        values = np.broadcast_to(np.asarray(component(points), float), (len(points),))
    else:
        values = np.full(len(points), float(component))
    if not np.all(np.isfinite(values)):
        raise ValueError("a boundary condition function returned NaN or infinite values")
    return values


def _load_name(instance, attribute, value) -> None:
    if not isinstance(value, str) or not value.strip():
        raise ValueError(
            f"{type(instance).__name__}.{attribute.name} must be a non-empty load name such as "
            f"'bulk', or None for a fixed traction; got {value!r}"
        )


@attrs.frozen
class Displacement:
    """Prescribed displacement; both components fixed at zero by default.

    Attributes
    ----------
    tag : str
    x, y : float, callable or None
    """

    tag: str
    x: Component = attrs.field(default=0.0, converter=_COMPONENT)
    y: Component = attrs.field(default=0.0, converter=_COMPONENT)


@attrs.frozen
class Traction:
    """Prescribed traction (force per length on the surface); zero by default.

    With ``load`` set, the values are per unit of that named load amplitude, which the load
    history drives (``LoadStep(loads={"bulk": sigma_B})``): ``Traction("end", x=1.0,
    load="bulk")`` is a bulk stress sigma_B on the end.

    Attributes
    ----------
    tag : str
    x, y : float, callable or None
    load : str or None
        Name of the history load scaling this traction (None: a fixed traction).
    """

    tag: str
    x: Component = attrs.field(default=0.0, converter=_COMPONENT)
    y: Component = attrs.field(default=0.0, converter=_COMPONENT)
    load: str | None = attrs.field(default=None, validator=attrs.validators.optional(_load_name))


@attrs.frozen
class LoadingBlock:
    """The segment moves as one rigid, non-rotating block with a prescribed resultant force.

    Its displacement (dx, dy) is unknown; the tractions on it add up to ``force``. This is
    how the reference scene loads the pad without fixing a node.

    Attributes
    ----------
    tag : str
    force : (float, float)
        Resultant force (Fx, Fy) per unit thickness applied to the body through the block.
    """

    tag: str
    force: tuple[float, float] = attrs.field(default=(0.0, 0.0), converter=_force)


Condition = Union[Displacement, Traction, LoadingBlock]  # noqa: UP007
