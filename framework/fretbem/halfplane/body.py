"""The half-plane body model: a semi-infinite elastic body with a discretised contact face.

Only the contact face is discretised (any basis family); its response comes in closed form
from :class:`~fretbem.halfplane.surface.HalfPlaneSurface`. A pad modelled as a half-plane
is driven by a loading block (the rigid far field: u += delta, and the block carries the
face's resultant); a specimen without a block responds to the history's ``"bulk"`` load, a
uniform far-field stress sigma_xx.
"""

from __future__ import annotations

from collections.abc import Mapping

import attrs
import numpy as np

from fretbem import registry as bases
from fretbem.basis import Basis, Refinement
from fretbem.bem import images
from fretbem.body import BlockRotation, Body, ContactFace, ContactResponse
from fretbem.conditions import LoadingBlock
from fretbem.geometry.nurbs import NurbsCurve
from fretbem.material import Material
from fretbem.numerics.scatter import added_at
from fretbem.validators import number_field

from .influence import DEFAULT_DATUM, HalfPlaneFaceError
from .joined import JoinedFace
from .stresses import HalfPlaneStressOperator
from .surface import HalfPlaneSurface

#: the history-driven load a half-plane specimen (no loading block) responds to
BULK = "bulk"


@attrs.frozen(eq=False)
class HalfPlaneSolution:
    """Surface fields of a solved half-plane body.

    Like a BEM body's solution, fields are evaluated per segment at curve parameters; the
    half-plane's segments are those of its contact face (one, or several joined, in
    boundary order). :meth:`surface_displacement` gives the displacement anywhere on the
    surface line.

    Attributes
    ----------
    body : HalfPlaneBody
    points : ndarray, shape (n, 2)
        Face nodes.
    tractions, displacements : ndarray, shape (n, 2)
        Traction on the body and displacement at the face nodes.
    block_displacement : ndarray, shape (2,)
    loads : dict
        Load amplitudes by name.
    rotation : float
        The loading block's rotation (rad, counterclockwise, about the block's centre
        :meth:`HalfPlaneBody.rotation_centre`); 0 for a block that does not rotate.
    """

    body: HalfPlaneBody
    points: np.ndarray
    tractions: np.ndarray
    displacements: np.ndarray
    block_displacement: np.ndarray
    loads: dict
    rotation: float = 0.0

    def surface_displacement(self, x, y=None) -> np.ndarray:
        """Surface displacement (m, 2) at abscissae ``x`` (anywhere on the surface line);
        ``y`` (m,), the points' heights, for the block rotation's share (default: the
        surface line)."""
        x = np.asarray(x, dtype=float).ravel()
        surface = self.body.surface
        u = surface.node_map(x) @ self.tractions.ravel()
        u += self.block_displacement if self.body.loading_block is not None else 0.0
        if BULK in self.body.load_names:
            u += surface.bulk_displacement(x) * self.loads.get(BULK, 0.0)
        if self.rotation:
            level = self.body.surface_level(x, self.body.side)
            points = np.column_stack([x, level if y is None else np.asarray(y, float).ravel()])
            u += self.rotation * rotation_field(points, self.body.rotation_centre())
        return u

    def _face(self, segment: int):
        parts = self.body.segments
        if not 0 <= segment < len(parts):
            raise IndexError(
                f"a half-plane body has {len(parts)} segment(s) (0 to {len(parts) - 1}, its "
                f"contact face), got {segment}"
            )
        return parts[segment]

    def _rows(self, segment: int) -> slice:
        sizes = np.cumsum([0] + [p.n_functions for p in self.body.segments])
        return slice(int(sizes[segment]), int(sizes[segment + 1]))

    def points_at(self, segment: int, params) -> np.ndarray:
        """Positions (m, 2) on the face profile at curve parameters."""
        face = self._face(segment)
        return face.geometry(*face.to_local(np.asarray(params, float)))[0]

    def displacement(self, segment: int, params) -> np.ndarray:
        """Displacement (m, 2) at curve parameters of a face segment."""
        points = self.points_at(segment, params)
        return self.surface_displacement(points[:, 0], points[:, 1])

    def traction(self, segment: int, params) -> np.ndarray:
        """Traction (m, 2) on the body at curve parameters of a face segment, interpolated."""
        face = self._face(segment)
        coefficients = np.linalg.solve(
            face.collocation_matrix(), self.tractions[self._rows(segment)]
        )
        return face.evaluation_matrix(np.asarray(params, float)) @ coefficients


def rotation_field(points: np.ndarray, centre) -> np.ndarray:
    """Displacement (m, 2) of ``points`` per unit rigid rotation about ``centre``: e_z x (p - c)."""
    arm = np.asarray(points, float) - np.asarray(centre, float)
    out = np.empty((len(arm), 2))  # np.column_stack([-arm[:, 1], arm[:, 0]]), no dispatch
    np.negative(arm[:, 1], out=out[:, 0])
    out[:, 1] = arm[:, 0]
    return out


def _face_curves(value) -> NurbsCurve | tuple[NurbsCurve, ...]:
    if isinstance(value, NurbsCurve):
        return value
    curves = tuple(value) if isinstance(value, list | tuple) else ()
    if not curves or not all(isinstance(c, NurbsCurve) for c in curves):
        raise HalfPlaneFaceError(
            f"a half-plane face is a NurbsCurve or a sequence of them, got {value!r}"
        )
    return curves[0] if len(curves) == 1 else curves


@attrs.frozen(eq=False)
class HalfPlaneBody(Body):
    """An elastic half-plane whose contact face is the only discretised boundary.

    The field ``loading_block`` (a LoadingBlock or None) is the rigid far field of a pad,
    driven by the load history (its tag is not used); without it the body is held at
    infinity and responds to the ``"bulk"`` load.

    Attributes
    ----------
    face : NurbsCurve or tuple of NurbsCurve
        The contact face's profile, running monotonically in x: a straight line for a flat
        specimen, the arc of a cylindrical pad, or several curves end to end in boundary
        order (a rounded flat's fillet, flat and fillet), each discretised at ``refinement``
        and their nodes joined in one face. Its points give the contact geometry; the
        elasticity is that of the half-plane under the straight surface (see
        :class:`~fretbem.halfplane.surface.HalfPlaneSurface`).
    material : Material
    side : str
        "lower": the body lies below its surface (a specimen, outward normal +y);
        "upper": above it (a pad, outward normal -y).
    basis : str or Basis subclass
        Basis family discretising the face.
    refinement : Refinement
    datum : float
        Distance (mm) from a line load at which its ln r displacement is zero (10 mm by
        default, a typical specimen thickness).
    bulk_origin : float
        x where the bulk-stress displacement is zero.
    tag : str
        The tag under which the face is known to contact pairs.
    name : str
    """

    face: NurbsCurve | tuple[NurbsCurve, ...] = attrs.field(converter=_face_curves)
    material: Material = attrs.field(validator=attrs.validators.instance_of(Material))
    side: str = "lower"
    basis: str | type[Basis] = "nurbs"
    refinement: Refinement = attrs.field(factory=Refinement)
    loading_block: LoadingBlock | None = None
    datum: float = attrs.field(
        default=DEFAULT_DATUM,
        converter=number_field(
            "the distance of zero ln r displacement, mm",
            "give a distance > 0 in mm (10 by default, about the specimen's thickness)",
            low=0.0,
            low_open=True,
        ),
    )
    bulk_origin: float = attrs.field(
        default=0.0,
        converter=number_field(
            "x where the bulk-stress displacement is zero, mm", "give x in mm (0 by default)"
        ),
    )
    tag: str = "contact"
    name: str = "half-plane"
    _cache: dict = attrs.field(init=False, factory=dict, repr=False)

    def __attrs_post_init__(self) -> None:
        if self.loading_block is not None and not isinstance(self.loading_block, LoadingBlock):
            raise HalfPlaneFaceError(
                f"body {self.name!r}: loading_block must be a LoadingBlock (for a pad driven "
                f"by the load history) or None (a specimen held at infinity), got "
                f"{self.loading_block!r}"
            )
        self.surface  # noqa: B018 - checks the side and the face now, not at first use

    @property
    def surface(self) -> HalfPlaneSurface:
        """The discretised surface operator (computed once).

        A face whose curve is the point image of one discretised before (the specimen of
        two similar cylinders, the pad's face reflected through the origin) takes that
        discretisation reflected: the same numbers, without discretising again
        (:func:`fretbem.bem.images.discretise`)."""
        if "surface" not in self._cache:
            family = bases.get(self.basis)
            parts = [images.discretise(family, curve, self.refinement) for curve in self.curves]
            face = parts[0] if len(parts) == 1 else JoinedFace(parts)
            self._cache["surface"] = HalfPlaneSurface(
                face, self.material, self.side, self.datum, self.bulk_origin,
                shared_as=(family.name, self.curves, self.refinement),
            )  # fmt: skip
        return self._cache["surface"]

    @property
    def curves(self) -> tuple[NurbsCurve, ...]:
        """The face's exact curves in boundary order (one for a single-segment face)."""
        return self.face if isinstance(self.face, tuple) else (self.face,)

    @property
    def segments(self) -> tuple[Basis, ...]:
        """The discretised boundary a writer can draw: the contact face's segments only."""
        face = self.surface.face
        return face.parts if isinstance(face, JoinedFace) else (face,)

    @property
    def segment_tags(self) -> tuple[str, ...]:
        """The face's tag, once per face segment."""
        return (self.tag,) * len(self.curves)

    @property
    def outline_complete(self) -> bool:
        """False: a half-plane has no far boundary to draw, only its face."""
        return False

    @property
    def finite(self) -> bool:
        """False: the half-plane idealisation is the one half-plane theory assumes."""
        return False

    @property
    def family(self) -> type[Basis]:
        """The face's basis family (resolved through the registry)."""
        return bases.get(self.basis)

    def face_curve(self, tag: str) -> NurbsCurve:
        """The face's exact curve (a face of one segment: the estimate refines one curve)."""
        self._check_tag(tag)
        if isinstance(self.face, tuple):
            raise HalfPlaneFaceError(
                f"body {self.name!r}: the half-plane face {tag!r} has {len(self.face)} "
                "segments; the error estimate and adaptive refinement need the contact face "
                "as one segment (set [contact] estimate = false and refine with pairs)"
            )
        return self.face

    def face_refinement(self, tag: str) -> Refinement:
        """The face's refinement."""
        self._check_tag(tag)
        return self.refinement

    def with_face_refinement(self, tag: str, refinement: Refinement) -> HalfPlaneBody:
        """A new half-plane body with its face at ``refinement``."""
        self._check_tag(tag)
        return attrs.evolve(self, refinement=refinement)

    def surface_level(self, x: np.ndarray, side: str) -> np.ndarray:
        """The straight surface line under the face (the half-plane's boundary)."""
        y = self.surface.points[:, 1]
        return np.full(np.shape(x), y.min() if side == "upper" else y.max())

    def stress_operator(self, points: np.ndarray, settings=None) -> HalfPlaneStressOperator:
        """Integrated Flamant line loads of the face tractions, plus the bulk stress."""
        return HalfPlaneStressOperator.of(self, np.asarray(points, float))

    @property
    def load_names(self) -> tuple[str, ...]:
        """("bulk",) for a specimen (no loading block); a pad responds to no named load."""
        return () if self.loading_block is not None else (BULK,)

    @property
    def dofs(self) -> int:
        """Unknowns of the discretised body: two traction components per face node."""
        return 2 * self.surface.face.n_functions

    def describe(self) -> dict:
        """Model, basis family and face degree for the run summary."""
        return {
            "model": "half-plane",
            "basis": bases.get(self.basis).name,
            "degree": self.surface.face.degree,
        }

    def _check_tag(self, tag: str) -> None:
        if tag != self.tag:
            raise KeyError(
                f"body {self.name!r} is a half-plane whose only face is tagged {self.tag!r}, "
                f"but tag {tag!r} was asked for; use {self.tag!r} in the contact pair"
            )

    def contact_face(self, tag: str) -> ContactFace:
        """The face nodes (collocation points of the face discretisation) and normals."""
        self._check_tag(tag)
        surface = self.surface
        return ContactFace(surface.points, surface.normals)

    def contact_response(self, tag: str) -> ContactResponse:
        """u = A t (+ delta for a pad, + eps(x) sigma_B for a specimen), in closed form."""
        self._check_tag(tag)
        if "response" not in self._cache:
            self._cache["response"] = self._response()
        return self._cache["response"]

    def rotation_centre(self) -> np.ndarray:
        """The loading block's centre: above (a pad) or below (a specimen) the face's middle,
        at the datum depth, where the rigid far field is held."""
        points = self.surface.points
        sign = 1.0 if self.side == "upper" else -1.0
        surface = points[:, 1].min() if self.side == "upper" else points[:, 1].max()
        return np.array([0.5 * (points[:, 0].min() + points[:, 0].max()),
                         surface + sign * self.datum])  # fmt: skip

    def _rotation(self, force: np.ndarray) -> BlockRotation:
        """The block's rotation: the far field turns rigidly; its moment balances the face's."""
        surface = self.surface
        points = surface.points
        n = len(points)
        centre = self.rotation_centre()
        # int phi (x - cx) |dx| and int phi (y - cy) |dx| per node value (E^-T, banded)
        moments = surface.per_node_value(
            _moment_integrals(surface.face, centre, surface.gauss_samples).T
        ).T
        contact_moment = np.zeros((n, 2))
        contact_moment[:, 0] = -moments[:, 1]
        contact_moment[:, 1] = moments[:, 0]
        contact_moment = contact_moment.ravel()
        return BlockRotation(
            centre=centre,
            level=float(centre[1]),
            face_map=rotation_field(points, centre),
            m_base=0.0,
            m_traction=-contact_moment,
            m_block=np.zeros(2),
            m_rotation=0.0,
            m_load=np.zeros(len(self.load_names)),
            r_rotation=np.zeros(2),
            contact_moment=contact_moment,
        )

    def _response(self) -> ContactResponse:
        surface = self.surface
        n = len(surface.points)
        force = surface.contact_force()
        has_block = self.loading_block is not None
        block_map = np.zeros((n, 2, 2))
        load_map = np.zeros((n, 2, len(self.load_names)))
        r_traction = np.zeros((2, 2 * n))
        if has_block:
            block_map[:, 0, 0] = block_map[:, 1, 1] = 1.0
            r_traction = -force  # the block balances the face tractions
        else:
            load_map[:, :, 0] = surface.bulk_displacement(surface.points[:, 0])
        arrays = {
            "base": np.zeros((n, 2)),
            "block_map": block_map,
            "load_map": load_map,
            "r_base": np.zeros(2),
            "r_traction": r_traction,
            "r_block": np.zeros((2, 2)),
            "r_load": np.zeros((2, len(self.load_names))),
            "contact_force": force,
        }
        for value in arrays.values():
            value.setflags(write=False)
        rotation = self._rotation(force) if has_block else None
        return ContactResponse(
            **arrays,
            # interleaved from the blocks only if asked: a node-to-node condensation reads
            # the blocks alone (the map is 7 MB and ~5 ms to build at 481 nodes)
            traction_map=None,
            has_block=has_block,
            rotation=rotation,
            traction_blocks=surface.traction_blocks,
        )

    def solution(
        self,
        tag: str,
        tractions: np.ndarray,
        block: np.ndarray,
        loads: Mapping[str, float],
        rotation: float = 0.0,
    ) -> HalfPlaneSolution:
        """Face tractions (n, 2) on the body, displacements at the nodes, block, loads and
        the block's rotation (rad, about :meth:`rotation_centre`)."""
        self._check_tag(tag)
        tractions = np.asarray(tractions, dtype=float).reshape(-1, 2)
        block = np.asarray(block, dtype=float)
        amplitudes = [float(loads.get(name, 0.0)) for name in self.load_names]
        response = self.contact_response(tag)
        u = response.displacement(tractions, block, amplitudes)
        if rotation:
            u = u + float(rotation) * response.rotation.face_map
        return HalfPlaneSolution(
            self, self.surface.points, tractions, u, block,
            {k: float(v) for k, v in loads.items()}, float(rotation),
        )  # fmt: skip


def _moment_integrals(face, centre, samples) -> np.ndarray:
    """int phi_b (x - cx) |dx| and int phi_b (y - cy) |dx| over the face (n_functions, 2),
    from the face's Gauss ``samples`` (:func:`~.influence.gauss_samples`)."""
    elements, rule_weights, m = samples
    weights = np.abs(m.tangents[:, 0]) * rule_weights
    out = np.zeros((face.n_functions, 2))
    for j in range(2):
        arm = (m.points[:, j] - centre[j]) * weights
        out[:, j] = added_at(face.n_functions, face.connectivity[elements],
                             m.values * arm[:, None])  # fmt: skip
    return out
