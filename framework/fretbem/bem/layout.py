"""Which boundary coefficient of a BEM body is known, and its value, from its conditions.

Every (function, component) coefficient pair is of one kind: TRACTION (traction known, the
displacement solved), DISPLACEMENT (the reverse), BLOCK (on a loading block: displacement
is the block's, traction solved) or CONTACT (left to the contact). Tractions scaled by a
named history load are kept apart, per unit of the load, so the load can vary per step.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import attrs
import numpy as np

from fretbem.conditions import Displacement, LoadingBlock, Traction, evaluate

if TYPE_CHECKING:  # pragma: no cover
    from fretbem.body import Body

#: kinds of each (function, component) coefficient pair
TRACTION, DISPLACEMENT, BLOCK, CONTACT = 0, 1, 2, 3


@attrs.frozen(eq=False)
class Layout:
    """Kinds and known coefficients of every (function, component) of a body, read-only.

    Attributes
    ----------
    kinds : ndarray of int, shape (N, 2)
    known : ndarray, shape (N, 2)
        Prescribed displacement or (fixed) traction coefficients; 0 elsewhere.
    loads : ndarray, shape (k, N, 2)
        Traction coefficients per unit of each named load, in ``load_names`` order.
    """

    kinds: np.ndarray
    known: np.ndarray
    loads: np.ndarray


def prescriptions(body: Body) -> dict[tuple[int, int], tuple[int, object, str | None]]:
    """(segment, component) -> (kind, value, load name) for every prescribed component."""
    table: dict[tuple[int, int], tuple[int, object, str | None]] = {}
    for condition in body.conditions:
        for segment in body.boundary.indices(condition.tag):
            for comp in range(2):
                if isinstance(condition, LoadingBlock):
                    entry = (BLOCK, condition.force[comp], None)
                else:
                    value = (condition.x, condition.y)[comp]
                    if value is None:
                        continue
                    if isinstance(condition, Displacement):
                        entry = (DISPLACEMENT, value, None)
                    else:
                        entry = (TRACTION, value, condition.load)
                if (segment, comp) in table:
                    raise ValueError(
                        f"body {body.name!r}: segment {segment} ({condition.tag!r}) has two "
                        f"conditions on its {'xy'[comp]} component; keep one"
                    )
                table[(segment, comp)] = entry
    return table


def load_names(body: Body) -> tuple[str, ...]:
    """Names of the history loads scaling the body's tractions, in order of appearance."""
    names = (c.load for c in body.conditions if isinstance(c, Traction) and c.load is not None)
    return tuple(dict.fromkeys(names))


def layout(body: Body, contact_tags: tuple[str, ...]) -> Layout:
    """The body's :class:`Layout` with the segments of ``contact_tags`` left to contact."""
    names = load_names(body)
    kinds = np.full((body.n_functions, 2), TRACTION)
    known = np.zeros((body.n_functions, 2))
    loads = np.zeros((len(names), body.n_functions, 2))
    contact_segments = {k for tag in contact_tags for k in body._indices(tag, "a contact")}
    table = prescriptions(body)
    for k, basis in enumerate(body.segments):
        sl = body.function_slice(k)
        if k in contact_segments:
            if any((k, c) in table for c in range(2)):
                raise ValueError(
                    f"body {body.name!r}: segment {k} ({body.boundary.segments[k].tag!r}) "
                    "is a contact segment and also has a boundary condition; remove one"
                )
            kinds[sl] = CONTACT
            continue
        points = None
        for comp in range(2):
            kind, value, load = table.get((k, comp), (TRACTION, 0.0, None))
            kinds[sl, comp] = kind
            if kind == BLOCK:
                continue
            target = known if load is None else loads[names.index(load)]
            if callable(value):
                if points is None:
                    elements, local = basis.collocation()
                    points = basis.geometry(elements, local)[0]
                values = evaluate(value, points)
                target[sl, comp] = np.linalg.solve(basis.collocation_matrix(), values)
            else:
                target[sl, comp] = float(value)  # partition of unity: constant coefficients
    for array in (kinds, known, loads):
        array.setflags(write=False)
    return Layout(kinds, known, loads)


def check_conditions(body: Body) -> None:
    """Reject unknown condition types, unknown tags, two blocks and conflicting conditions."""
    for condition in body.conditions:
        if not isinstance(condition, (Displacement, Traction, LoadingBlock)):
            raise TypeError(f"body {body.name!r}: unknown boundary condition {condition!r}")
        body._indices(condition.tag, f"a {type(condition).__name__} condition")
    for tag in body.refinement:
        body._indices(tag, "a refinement")
    blocks = [c for c in body.conditions if isinstance(c, LoadingBlock)]
    if len(blocks) > 1:
        raise ValueError(f"body {body.name!r} has {len(blocks)} loading blocks; at most one")
    prescriptions(body)  # raises on conflicting conditions
