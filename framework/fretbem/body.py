"""What a contact simulation needs from an elastic body: the abstract :class:`Body`.

A body model (the BEM body of :mod:`fretbem.bem.body`, a half-plane, ...) only has to
give its discretised contact face and its displacement there as an affine function of the
face tractions, its loading-block displacement and its named loads (the
:class:`ContactResponse`); the contact condensation, the solvers and the results use
nothing else. docs/how-to/new-body-model.rst shows how to add one.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Mapping
from typing import Any

import attrs
import numpy as np

from fretbem.errors import InputError, UnsupportedError

from .basis import Basis, Refinement
from .conditions import LoadingBlock
from .geometry.nurbs import NurbsCurve
from .material import Material


class RigidMotionError(InputError):
    """The boundary conditions leave a rigid-body motion of a body undetermined."""


@attrs.frozen(eq=False)
class ContactFace:
    """The nodes of a body's discretised contact face (collocation points for BEM).

    Attributes
    ----------
    points, normals : ndarray, shape (n, 2)
        Node positions and unit outward normals, in the body's own node order.
    """

    points: np.ndarray
    normals: np.ndarray

    @property
    def n_nodes(self) -> int:
        """Number of face nodes."""
        return len(self.points)


@attrs.frozen(eq=False)
class BlockRotation:
    """How the face and the block's moment respond to a rotation of the loading block.

    A rotation theta (rad, counterclockwise) of the block about ``centre`` moves the face
    by theta e_z x (p - centre); the block's moment on the body about ``centre``
    (counterclockwise, force x length per thickness) is affine like its force::

        u += face_map * theta
        M = m_base + m_traction @ t.ravel() + m_block @ delta + m_rotation * theta + m_load @ beta
        R += r_rotation * theta

    Attributes
    ----------
    centre : ndarray, shape (2,)
        The point the rotation and the moments refer to.
    level : float
        y of the block's line (the pad's top for a BEM pad, the datum depth of a half-plane):
        where a rig's pivot sits by default.
    face_map : ndarray, shape (n, 2)
    m_base : float; m_traction : (2n,); m_block : (2,); m_rotation : float; m_load : (k,)
    r_rotation : ndarray, shape (2,)
    contact_moment : ndarray, shape (2n,)
        Moment of the face tractions about ``centre`` per unit node traction (the block's
        moment balances it, to round-off on a half-plane, to the discretisation on a BEM
        body).
    """

    centre: np.ndarray
    level: float
    face_map: np.ndarray
    m_base: float
    m_traction: np.ndarray
    m_block: np.ndarray
    m_rotation: float
    m_load: np.ndarray
    r_rotation: np.ndarray
    contact_moment: np.ndarray


@attrs.frozen(eq=False)
class ContactResponse:
    """Displacement at the face nodes, affine in the face tractions, block and loads.

    With t (n, 2) the traction vector on this body at each face node (global x, y), delta
    the loading-block displacement (2,) and beta the load amplitudes (k,) in the order of
    ``Body.load_names``::

        u = base + traction_map @ t.ravel() + block_map @ delta + load_map @ beta
        R = r_base + r_traction @ t.ravel() + r_block @ delta + r_load @ beta

    R is the force the loading block applies to the body (zeros without a block).

    Attributes
    ----------
    base : ndarray, shape (n, 2)
    traction_map : ndarray, shape (n, 2, 2n)
        Column 2 a + j: unit traction component j at node a. Given as None with
        ``traction_blocks``, it is interleaved from them at first use (the condensation of
        a node-to-node pairing reads only the blocks; the map is twice their memory).
    block_map : ndarray, shape (n, 2, 2)
    load_map : ndarray, shape (n, 2, k)
    r_base : ndarray, shape (2,); r_traction : (2, 2n); r_block : (2, 2); r_load : (2, k)
    contact_force : ndarray, shape (2, 2n)
        Resultant force of the face tractions per unit node traction (the integral of the
        traction field over the face, for any body model).
    has_block : bool
        Whether the body carries a loading block (its delta is then an unknown).
    rotation : BlockRotation or None
        The response to the block's rotation; None without a block, or where the body model
        cannot rotate it (a BEM body held by Displacement conditions as well).
    traction_blocks : tuple of two ndarrays (n, n), or None
        (A, B) where ``traction_map`` is ``[[A, B], [-B, A]]`` per node pair (component
        rows x, y; columns x, y), as a half-plane's is: the condensation then works on the
        two blocks instead of the (n, 2, 2n) map. None for a map of no such form.
    """

    base: np.ndarray
    _traction_map: np.ndarray | None = attrs.field(alias="traction_map")
    block_map: np.ndarray
    load_map: np.ndarray
    r_base: np.ndarray
    r_traction: np.ndarray
    r_block: np.ndarray
    r_load: np.ndarray
    contact_force: np.ndarray
    has_block: bool
    rotation: BlockRotation | None = None
    traction_blocks: tuple[np.ndarray, np.ndarray] | None = None
    _built: dict = attrs.field(init=False, factory=dict, repr=False)

    def __attrs_post_init__(self) -> None:
        if self._traction_map is None and self.traction_blocks is None:
            raise TypeError("ContactResponse needs traction_map or traction_blocks")

    @property
    def traction_map(self) -> np.ndarray:
        """The (n, 2, 2n) map (interleaved from ``traction_blocks`` at first use if not given)."""
        if self._traction_map is not None:
            return self._traction_map
        if "traction_map" not in self._built:
            built = interleaved_map(*self.traction_blocks)
            built.setflags(write=False)
            self._built["traction_map"] = built
        return self._built["traction_map"]

    @property
    def n_nodes(self) -> int:
        """Number of face nodes."""
        return len(self.base)

    def displacement(self, tractions, block=(0.0, 0.0), loads=()) -> np.ndarray:
        """u (n, 2) at the face nodes for node tractions (n, 2), block delta and loads."""
        beta = np.asarray(loads, float).reshape(-1)
        return (
            self.base
            + self.traction_map @ np.asarray(tractions, float).ravel()
            + self.block_map @ np.asarray(block, float)
            + self.load_map @ beta
        )


def interleaved_map(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The (m, 2, 2N) map ``[[A, B], [-B, A]]`` per node pair (column 2 b + j) of two (m, N)
    blocks."""
    m, n = a.shape
    out = np.empty((m, 2, n, 2))
    out[:, 0, :, 0] = a
    out[:, 0, :, 1] = b
    out[:, 1, :, 0] = -b
    out[:, 1, :, 1] = a
    return out.reshape(m, 2, 2 * n)


class Body(ABC):
    """An elastic body seen by the contact: a face, its response and its fields.

    Implementations: :class:`fretbem.bem.body.BemBody` (finite body, boundary elements)
    and the half-plane body. ``check_body`` in :mod:`fretbem.testing` checks the contract.

    Attributes
    ----------
    name : str
    material : Material
    """

    name: str
    material: Material

    @property
    @abstractmethod
    def loading_block(self) -> LoadingBlock | None:
        """The rigid block through which the load history drives the body, if any."""

    @property
    def load_names(self) -> tuple[str, ...]:
        """History-driven scalar loads the body responds to (e.g. ``("bulk",)``)."""
        return ()

    @property
    def timings(self) -> dict[str, float]:
        """Wall times (s) of the work done so far (assembly, factorisation); may be empty."""
        return {}

    @property
    @abstractmethod
    def dofs(self) -> int:
        """Number of unknowns of the discretised body (reported in the run summary)."""

    def describe(self) -> dict[str, Any]:
        """Facts for the run summary (model, basis, degree); override to add more."""
        return {"model": type(self).__name__}

    @abstractmethod
    def contact_face(self, tag: str) -> ContactFace:
        """The nodes of the face ``tag`` (raises KeyError naming the tag if unknown)."""

    @abstractmethod
    def contact_response(self, tag: str) -> ContactResponse:
        """The face's displacement response (computed once and cached by the body).

        Raises :class:`RigidMotionError` if the body is not held once its face is in
        contact (a loading block counts as holding it).
        """

    @abstractmethod
    def solution(
        self, tag: str, tractions: np.ndarray, block: np.ndarray, loads: Mapping[str, float]
    ) -> Any:
        """The body's fields for face node tractions (n, 2), block delta (2,) and loads.

        A body whose response has a :class:`BlockRotation` also takes ``rotation=theta``
        (rad, about its ``centre``; the contact passes it only when the block rotates).

        The returned object gives ``displacement(k, params)`` and ``traction(k, params)``
        (n, 2) on segment k of :attr:`segments` at curve parameters, and
        ``block_displacement``; the outputs read it through these only.
        """

    # -- what the outputs ask of a body (VTK, figures, stresses, estimate, re-mesh) ----------
    # Each has a default that says the model does not provide it (UnsupportedError), so an
    # output that cannot apply to a model is skipped with one line instead of crashing.
    @property
    def segments(self) -> tuple[Basis, ...]:
        """The discretised segments whose fields the body reports (drawn and sampled)."""
        return ()

    @property
    def segment_tags(self) -> tuple[str, ...]:
        """The tag of each of :attr:`segments`."""
        return ()

    @property
    def outline_complete(self) -> bool:
        """True when :attr:`segments` outline the whole body (a half-plane has only its face)."""
        return True

    @property
    def finite(self) -> bool:
        """True for a body of finite extent, whose contact differs from half-plane theory by
        its size and shape as well as by the discretisation (False for a half-plane)."""
        return True

    @property
    def family(self) -> type[Basis]:
        """The basis family of the contact face (the estimate and re-mesh refine with it)."""
        raise UnsupportedError(
            f"the {self.describe().get('model', type(self).__name__)} body {self.name!r} "
            "has no basis family to refine"
        )

    def face_segment(self, tag: str) -> tuple[int, Basis]:
        """Index and discretised segment of the one segment tagged ``tag`` (a contact face)."""
        indices = [k for k, t in enumerate(self.segment_tags) if t == tag]
        if not self.segments:
            raise UnsupportedError(
                f"the {self.describe().get('model', type(self).__name__)} body {self.name!r} "
                "has no discretised segments"
            )
        if len(indices) != 1:
            raise InputError(
                f"body {self.name!r}: the contact tag {tag!r} names {len(indices)} segments; the "
                "error estimate and adaptive refinement need the contact face as one segment"
            )
        return indices[0], self.segments[indices[0]]

    def face_curve(self, tag: str) -> NurbsCurve:
        """The exact geometry of the face ``tag``, before any refinement."""
        raise UnsupportedError(
            f"the {self.describe().get('model', type(self).__name__)} body {self.name!r} "
            "has no exact face curve"
        )

    def face_refinement(self, tag: str) -> Refinement:
        """How the face ``tag`` is discretised now."""
        raise UnsupportedError(
            f"the {self.describe().get('model', type(self).__name__)} body {self.name!r} "
            "has no face refinement"
        )

    def with_face_refinement(self, tag: str, refinement: Refinement) -> Body:
        """The same body with the face ``tag`` discretised at ``refinement`` (a new body)."""
        raise UnsupportedError(
            f"the {self.describe().get('model', type(self).__name__)} body {self.name!r} "
            "cannot be re-meshed"
        )

    def surface_level(self, x: np.ndarray, side: str) -> np.ndarray:
        """y of the contact-side surface at abscissae x (where stress lines start): the
        highest boundary crossing of the vertical line for the lower body (``side`` "lower"),
        the lowest for the upper body; +-inf where the line misses the body."""
        x = np.asarray(x, float)
        # each abscissa once: a map's grid or a depth line repeats its x for every depth
        flat, inverse = np.unique(x.ravel(), return_inverse=True)
        best = np.full(flat.shape, -np.inf if side == "lower" else np.inf)
        t = np.linspace(0.0, 1.0, 401)
        for basis in self.segments:
            pts = basis.curve.points(t)
            x0, x1 = pts[:-1, 0], pts[1:, 0]
            lo, hi = np.minimum(x0, x1), np.maximum(x0, x1)
            # every (abscissa, chord) crossing at once: one batched bisection per segment
            hit = (flat[:, None] >= lo) & (flat[:, None] <= hi) & (hi > lo)
            ix, k = np.nonzero(hit)
            if ix.size == 0:
                continue
            # refine the crossing on the exact curve by bisection in the parameter
            a, b = t[k], t[k + 1]
            target, increasing = flat[ix], (x1 > x0)[k]
            for _ in range(50):
                mid = 0.5 * (a + b)
                move = (basis.curve.points(mid)[:, 0] > target) == increasing
                b = np.where(move, mid, b)
                a = np.where(move, a, mid)
            y = basis.curve.points(0.5 * (a + b))[:, 1]
            if side == "lower":
                np.maximum.at(best, ix, y)
            else:
                np.minimum.at(best, ix, y)
        return best[inverse].reshape(x.shape)

    def stress_operator(self, points: np.ndarray, settings: Any = None) -> Any:
        """Stresses at interior ``points`` (m, 2) as an object with ``evaluate(solution)``
        -> (m, 4) [sxx, syy, sxy, szz]; built once, applied to every step's solution."""
        raise UnsupportedError(
            f"the {self.describe().get('model', type(self).__name__)} body {self.name!r} "
            "provides no stress evaluation"
        )
