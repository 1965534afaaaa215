"""Node integrals shared by half-plane faces with the same x-projection (pad and specimen).

The influence coefficients of a half-plane face depend only on the face's projection on
the surface line, x(xi) with its shape functions, and on the datum; the material and the
side enter later as constants. Two cylinders pressed together, or any pad on a specimen
whose face copies the pad's, give both bodies faces with the same projection, traversed in
opposite directions: the costly integrals are then computed once, for whichever face asks
first, and handed to the other with its nodes reversed.

The key is the content that fixes the projection: the basis family, the face's curves in
the direction of increasing x (a face running the other way is reversed when its refinement
is uniform, so reversing it gives the same elements), their control points measured into
the body (y for a body above its surface, -y below: the profile's shape, which a family
placing nodes by arc length would see), the refinement and the datum. A face that joins an
entry must also have the entry's node abscissae (to 1e-12 of the face's span), or it
computes its own. Entries live while a surface holds them (weak references), so a large
problem keeps no copy once its bodies are gone.
"""

from __future__ import annotations

import weakref
from collections.abc import Callable, Sequence

import numpy as np

from fretbem.basis import Refinement
from fretbem.geometry.nurbs import NurbsCurve

#: node abscissae of two faces sharing integrals agree to this fraction of the face's span
NODE_TOLERANCE = 1e-12


class SharedIntegrals:
    """The node integrals of one projection, in the order of increasing x, computed once.

    Kept only until every face that joined has taken them (``members``, ``served``): each
    face builds its own traction map from them, so a kept copy would only cost memory.
    """

    def __init__(self, nodes: np.ndarray):
        self.nodes = nodes  # node abscissae, increasing-x order
        self.value: np.ndarray | None = None
        self.members = self.served = 0
        #: whether a member's face passed the face check (x monotone: the projection's
        #: property, so a twin need not map its Gauss points again to check it)
        self.checked = False
        #: int phi_a |dx| per unit node value, increasing-x order (n numbers, kept while
        #: the entry lives): the face's force per unit node traction
        self.weights: np.ndarray | None = None

    def matches(self, nodes: np.ndarray) -> bool:
        """Whether a face with node abscissae ``nodes`` (increasing-x order) has these."""
        if nodes.shape != self.nodes.shape:
            return False
        span = max(float(np.ptp(self.nodes)), 1e-300)
        return bool(np.all(np.abs(nodes - self.nodes) <= NODE_TOLERANCE * span))


class NodeIntegrals:
    """How one face gets its node integrals: from a shared entry, or computed alone.

    ``get(compute)`` returns the (2 n, n) ln and sign integrals per unit node value at the
    face's own nodes, in the face's node order; ``compute()`` gives them for this face.
    """

    def __init__(self, shared: SharedIntegrals | None, reverse: bool):
        self.shared, self.reverse = shared, reverse

    def get(self, compute: Callable[[], np.ndarray]) -> np.ndarray:
        """The integrals in this face's node order (computed by ``compute`` when first asked)."""
        shared = self.shared
        if shared is None:
            return compute()
        shared.served += 1
        if shared.value is None:
            value = compute()
            if shared.served < shared.members:  # a twin will ask
                value.setflags(write=False)
                shared.value = _reversed(value) if self.reverse else value
            return value
        value = _reversed(shared.value) if self.reverse else shared.value
        if shared.served >= shared.members:
            shared.value = None
        return value

    def force_weights(self, compute: Callable[[], np.ndarray]) -> np.ndarray:
        """int phi_a |dx| per unit node value in this face's node order, computed by
        ``compute`` for the first member that asks and handed to its twin reversed."""
        shared = self.shared
        if shared is None:
            return compute()
        if shared.weights is None:
            weights = compute()
            weights.setflags(write=False)
            shared.weights = weights[::-1] if self.reverse else weights
            return weights
        return shared.weights[::-1] if self.reverse else shared.weights


def _reversed(both: np.ndarray) -> np.ndarray:
    """(2 n, n) integrals of stacked ln and sign blocks with the node order reversed."""
    n = both.shape[1]
    out = np.concatenate([both[:n][::-1, ::-1], both[n:][::-1, ::-1]])
    out.setflags(write=False)
    return out


_entries: weakref.WeakValueDictionary = weakref.WeakValueDictionary()


def node_integrals(
    family: str,
    curves: Sequence[NurbsCurve],
    refinement: Refinement,
    side: str,
    datum: float,
    nodes: np.ndarray,
    check: Callable[[], None] | None = None,
) -> NodeIntegrals:
    """The sharing of a face of ``curves`` (discretised by ``family`` at ``refinement``)
    whose nodes lie at abscissae ``nodes``, joined as one more member; a face without a
    twin shares with nobody yet. ``check`` (the face check, raising on a bad face) runs
    before joining unless a twin already passed it."""
    nodes = np.asarray(nodes, float)
    reverse = bool(nodes.size > 1 and nodes[-1] < nodes[0])
    uniform = refinement.toward is None and refinement.at is None and not refinement.c0_at
    if reverse and uniform:
        curves = [curve.reversed() for curve in reversed(curves)]
        nodes = nodes[::-1]
    elif reverse:  # a graded face reversed is graded the other way: no twin across direction
        family = (family, "reversed")
    into_body = 1.0 if side == "upper" else -1.0
    key = (
        family,
        tuple(
            (curve.degree, curve.knots.tobytes(), curve.weights.tobytes(),
             curve.control_points[:, 0].tobytes(),
             (into_body * curve.control_points[:, 1] + 0.0).tobytes())
            for curve in curves
        ),
        refinement,
        float(datum),
    )  # fmt: skip
    shared = _entries.get(key)
    if shared is None or not shared.matches(nodes):
        shared = SharedIntegrals(nodes)
        _entries[key] = shared
    if check is not None and not shared.checked:
        check()
        shared.checked = True
    shared.members += 1
    return NodeIntegrals(shared, reverse and uniform)
