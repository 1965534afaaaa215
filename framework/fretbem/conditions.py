"""Boundary conditions per tagged segment: displacement, traction, rigid loading block.

A component given as a number is uniform; a callable receives points (m, 2) and returns
(m,) values. ``None`` leaves the component to another condition (a segment component that
no condition names is traction free).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Union

import attrs
import numpy as np

from .validators import finite

Component = Union[float, Callable[[np.ndarray], np.ndarray], None]  # noqa: UP007


def _component(instance, attribute, value) -> None:
    if value is None or callable(value):
        return
    finite(instance, attribute, value)


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
    x: Component = attrs.field(default=0.0, validator=_component)
    y: Component = attrs.field(default=0.0, validator=_component)


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
    x: Component = attrs.field(default=0.0, validator=_component)
    y: Component = attrs.field(default=0.0, validator=_component)
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
    force: tuple[float, float] = attrs.field(
        default=(0.0, 0.0), converter=lambda f: tuple(float(v) for v in f), validator=finite
    )


Condition = Union[Displacement, Traction, LoadingBlock]  # noqa: UP007
