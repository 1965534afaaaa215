"""Scene factories: the reference Cattaneo-Mindlin fretting cycle (docs/theory.md).

Each body's face is split into three segments: a candidate contact zone of half-width
``zone`` x (Hertz half-width) holding exactly ``pairs`` collocation points, and two flanks
graded away from it; sides, top and bottom are coarse.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping, Sequence

import attrs
import numpy as np

from fretbem import registry as bases
from fretbem.basis import Basis, Refinement
from fretbem.bem.body import BemBody
from fretbem.body import Body
from fretbem.conditions import Condition, Displacement, LoadingBlock
from fretbem.contact.law import CoulombFriction
from fretbem.contact.pairs import NodeToNodePair
from fretbem.geometry.boundary import Boundary, Segment
from fretbem.geometry.nurbs import NurbsCurve
from fretbem.halfplane.scene import half_plane_model
from fretbem.material import Material
from fretbem.simulation import LoadStep, Simulation
from fretbem.solvers.newton import SemiSmoothNewton, Solver
from fretbem.validators import count, finite, non_negative, poisson, positive
from fretbem.verification.closed_forms import HertzLineContact, MindlinDeresiewicz, dundurs_beta

from .builder import CORNER_RATIO, grading_ratio, zone_elements

REFERENCE_STEPS = ("A", "B", "C", "D", "E")


@attrs.frozen
class CattaneoMindlinScene:
    """Parameters of the reference scene (defaults are the scene file's values).

    Attributes
    ----------
    basis : str or Basis subclass
    pairs : int
        Node pairs in the candidate contact zone.
    zone : float
        Candidate zone half-width over the Hertz half-width.
    degree : int or None
        Basis degree (nurbs family); None for the family default.
    radius, width, height : float
        R, w, h in mm.
    lower : str
        "arc" (two similar bodies) or "flat" (pad on a flat specimen).
    E_upper, nu_upper, E_lower, nu_lower : float
    friction : float
    normal : float
        P, N/mm.
    tangential : sequence of float
        Q at the end of each step.
    names : sequence of str
    increments : int
        Sub-increments per step.
    flank_elements, side_elements, top_elements : int
        Elements on each flank, side and top/bottom.
    models : mapping of "upper"/"lower" to str
        Body model per body: "bem" (default) or a name registered in ``BODY_MODELS``.
    """

    basis: str | type[Basis] = "nurbs"
    pairs: int = attrs.field(default=61, validator=count)
    zone: float = attrs.field(default=1.5, validator=positive)
    degree: int | None = None
    radius: float = attrs.field(default=70.0, validator=positive)
    width: float = attrs.field(default=6.5, validator=positive)
    height: float = attrs.field(default=16.25, validator=positive)
    lower: str = attrs.field(default="arc", validator=attrs.validators.in_(("arc", "flat")))
    E_upper: float = attrs.field(default=73400.0, validator=positive)
    nu_upper: float = attrs.field(default=0.33, validator=poisson)
    E_lower: float = attrs.field(default=73400.0, validator=positive)
    nu_lower: float = attrs.field(default=0.33, validator=poisson)
    friction: float = attrs.field(default=0.3, validator=non_negative)
    normal: float = attrs.field(default=100.0, validator=positive)
    tangential: Sequence[float] = attrs.field(
        default=(0.0, 18.0, 0.0, -18.0, 0.0), converter=tuple, validator=finite
    )
    names: Sequence[str] = attrs.field(default=REFERENCE_STEPS, converter=tuple)
    increments: int = attrs.field(default=1, validator=count)
    flank_elements: int = attrs.field(default=16, validator=count)
    side_elements: int = attrs.field(default=12, validator=count)
    top_elements: int = attrs.field(default=12, validator=count)
    models: Mapping[str, str] = attrs.field(factory=dict, converter=lambda m: dict(m), hash=False)

    def __attrs_post_init__(self) -> None:
        if len(self.names) != len(self.tangential):
            raise ValueError(
                f"the scene has {len(self.names)} step names but {len(self.tangential)} "
                "tangential loads; give one name per load step"
            )

    def hertz(self) -> HertzLineContact:
        """Hertz line contact of the scene (two arcs, or arc on flat)."""
        return HertzLineContact.from_bodies(
            load=self.normal,
            radius_upper=self.radius,
            radius_lower=self.radius if self.lower == "arc" else math.inf,
            E_upper=self.E_upper,
            nu_upper=self.nu_upper,
            E_lower=self.E_lower,
            nu_lower=self.nu_lower,
        )

    def reference(self) -> MindlinDeresiewicz | None:
        """Mindlin-Deresiewicz reference, or None for dissimilar materials (coupled problem)."""
        beta = dundurs_beta(self.E_upper, self.nu_upper, self.E_lower, self.nu_lower)
        if abs(beta) > 1e-12:
            return None
        return MindlinDeresiewicz(self.hertz(), self.friction)

    def zone_elements(self, family: type[Basis]) -> int:
        """Elements on the zone segment giving exactly ``pairs`` collocation points."""
        return zone_elements(family, self.pairs, self.degree)


def _arcs(center_y: float, radius: float, angles: Sequence[float]) -> list[NurbsCurve]:
    center = np.array([0.0, center_y])
    return [NurbsCurve.arc(center, radius, a0, a1) for a0, a1 in itertools.pairwise(angles)]


FACE_TAGS = ("flank_left", "contact", "flank_right")


def upper_boundary(radius: float, half_width: float, height: float, zone: float) -> Boundary:
    """The pad: arc face (lowest point at the origin) split at +-zone, sides, top at y = h."""
    phi_w, phi_z = math.asin(half_width / radius), math.asin(zone / radius)
    down = -math.pi / 2
    face = _arcs(radius, radius, [down - phi_w, down - phi_z, down + phi_z, down + phi_w])
    left, right = face[0].points([0.0])[0], face[-1].points([1.0])[0]
    return Boundary(
        [Segment(tag, c) for tag, c in zip(FACE_TAGS, face, strict=True)]
        + [
            Segment("side_right", NurbsCurve.line(right, [half_width, height])),
            Segment("top", NurbsCurve.line([half_width, height], [-half_width, height])),
            Segment("side_left", NurbsCurve.line([-half_width, height], left)),
        ]
    )


def lower_boundary(
    radius: float, half_width: float, height: float, zone: float, flat: bool = False
) -> Boundary:
    """The specimen: mirror image of the pad about y = 0, or with a flat face (same x(xi))."""
    phi_w, phi_z = math.asin(half_width / radius), math.asin(zone / radius)
    up = math.pi / 2
    face = _arcs(-radius, radius, [up - phi_w, up - phi_z, up + phi_z, up + phi_w])
    if flat:
        face = [c.flattened(0.0) for c in face]
    right, left = face[0].points([0.0])[0], face[-1].points([1.0])[0]
    tags = FACE_TAGS[::-1]  # the top face runs right to left
    return Boundary(
        [
            Segment("bottom", NurbsCurve.line([-half_width, -height], [half_width, -height])),
            Segment("side_right", NurbsCurve.line([half_width, -height], right)),
        ]
        + [Segment(tag, c) for tag, c in zip(tags, face, strict=True)]
        + [Segment("side_left", NurbsCurve.line(left, [-half_width, -height]))]
    )


def _refinements(scene: CattaneoMindlinScene, family: type[Basis], upper: bool) -> dict:
    """Zone uniform; flanks graded toward the zone; sides, top and bottom toward corners.

    The loaded/fixed edge meets the free sides at corners where the traction is singular;
    grading toward them keeps each body's equilibrium error near 0.01 % of the load.
    """
    zone = scene.zone * scene.hertz().half_width
    zone_elements = scene.zone_elements(family)
    zone_size = 2 * zone / zone_elements
    flank = grading_ratio(scene.width / 2 - zone, scene.flank_elements, 2 * zone_size)
    # parameter end of each flank nearest the zone (the lower face runs right to left)
    near_zone = {"flank_left": 1.0, "flank_right": 0.0}
    if not upper:
        near_zone = {tag: 1.0 - end for tag, end in near_zone.items()}
    coarse = Refinement.graded(scene.top_elements, (0.0, 1.0), CORNER_RATIO, degree=scene.degree)
    levels = {
        "contact": Refinement(elements=zone_elements, degree=scene.degree),
        "top" if upper else "bottom": coarse,
        "side_left": Refinement.graded(
            scene.side_elements, (0.0, 1.0), CORNER_RATIO, degree=scene.degree
        ),
    }
    levels["side_right"] = levels["side_left"]
    for tag, end in near_zone.items():
        levels[tag] = Refinement.graded(scene.flank_elements, end, flank, degree=scene.degree)
    return levels


def cattaneo_mindlin(
    scene: CattaneoMindlinScene | None = None, *, solver: Solver | None = None, **overrides
) -> Simulation:
    """Build the reference fretting simulation (overrides are CattaneoMindlinScene fields).

    ``solver`` replaces the default :class:`~fretbem.solvers.newton.SemiSmoothNewton`; the body
    models come from ``scene.models`` (see :func:`body_model`).
    """
    scene = attrs.evolve(scene or CattaneoMindlinScene(), **overrides)
    family = bases.get(scene.basis)
    zone = scene.zone * scene.hertz().half_width
    if not 0 < zone < scene.width / 2:
        raise ValueError(
            f"the candidate zone half-width {zone:.4g} mm must lie inside the face (half-width "
            f"{scene.width / 2:g} mm); lower 'zone' or widen the bodies"
        )
    w2, h, radius = scene.width / 2, scene.height, scene.radius
    upper = body_model(
        "upper",
        scene=scene,
        boundary=upper_boundary(radius, w2, h, zone),
        material=Material(scene.E_upper, scene.nu_upper),
        conditions=[LoadingBlock("top", (0.0, -scene.normal))],
        family=family,
        refinement=_refinements(scene, family, upper=True),
    )
    lower = body_model(
        "lower",
        scene=scene,
        boundary=lower_boundary(radius, w2, h, zone, flat=scene.lower == "flat"),
        material=Material(scene.E_lower, scene.nu_lower),
        conditions=[Displacement("bottom")],
        family=family,
        refinement=_refinements(scene, family, upper=False),
    )
    steps = tuple(
        LoadStep(name, scene.normal, q, scene.increments)
        for name, q in zip(scene.names, scene.tangential, strict=True)
    )
    return Simulation(
        NodeToNodePair(upper, lower),
        steps,
        solver or SemiSmoothNewton(),
        law=CoulombFriction(scene.friction),
        reference=scene.reference(),
        name="cattaneo-mindlin",
    )


def _half_plane(label: str, **description) -> Body:
    """The half-plane model (imported on first use)."""

    return half_plane_model(label, **description)


#: body models a scene can choose per body: name -> factory (see :func:`body_model`)
BODY_MODELS: dict = {"half-plane": _half_plane}


def body_model(
    label: str,
    *,
    scene: CattaneoMindlinScene,
    boundary: Boundary,
    material: Material,
    conditions: Sequence[Condition],
    family: type[Basis],
    refinement: dict,
) -> Body:
    """The body ``label`` ("upper" or "lower") in the model the scene chooses for it.

    ``scene.models[label]`` names the model: "bem" (the default, :class:`BemBody`) or a
    model registered in :data:`BODY_MODELS` (a factory taking the same keywords).
    """
    model = dict(scene.models).get(label, "bem")
    if model == "bem":
        return BemBody(
            boundary, material, conditions, basis=family, refinement=refinement, name=label
        )
    try:
        factory = BODY_MODELS[model]
    except KeyError:
        raise ValueError(
            f"unknown body model {model!r} for the {label} body; choose 'bem' or one of "
            f"{sorted(BODY_MODELS)}"
        ) from None
    return factory(
        label,
        scene=scene,
        boundary=boundary,
        material=material,
        conditions=conditions,
        family=family,
        refinement=refinement,
    )
