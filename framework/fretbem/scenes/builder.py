"""Turn a :class:`~fretbem.scenes.spec.Scene` into a :class:`~fretbem.simulation.Simulation`.

The contact segments of both bodies hold exactly ``pairs`` collocation points each
(facing node to node); the flanks are graded toward the zone, sides and ends toward their
corners (where the traction is singular). The closed-form reference is chosen from the
scene: Mindlin-Deresiewicz without bulk stress, Nowell-Hills with sigma_B in phase with Q,
none where neither applies (the reason is kept for the report).
"""

from __future__ import annotations

import math

import attrs

from fretbem import registry
from fretbem.basis import Basis, Refinement, points_per_element
from fretbem.conditions import Displacement, LoadingBlock, Traction
from fretbem.contact.pairs import NodeToNodePair
from fretbem.simulation import LoadStep, Simulation
from fretbem.verification.closed_forms import HertzLineContact, MindlinDeresiewicz, dundurs_beta
from fretbem.verification.nowell_hills import NowellHills

from .limits import check_scene
from .spec import Scene, SceneFileError

__all__ = ["CORNER_RATIO", "build", "grading_ratio", "hertz", "reference", "zone_elements"]

#: element size ratio on sides, ends, top and bottom, graded toward their corners
CORNER_RATIO = 50.0
#: largest Hertz half-width over the smaller face radius where the half-plane closed forms
#: (Hertz, Mindlin-Deresiewicz, Nowell-Hills) are compared: they assume a << R
MAX_A_OVER_R = 0.1


def zone_elements(family: type[Basis], pairs: int, degree: int | None) -> int:
    """Elements on one contact segment giving exactly ``pairs`` collocation points."""
    per_element, extra = points_per_element(family, degree)
    elements = (pairs - extra) / per_element
    if elements < 1 or elements != int(elements):
        raise ValueError(
            f"the {family.name} family cannot put exactly {pairs} collocation points in the "
            f"contact zone (it gives {per_element:g} per element + {extra:g}); choose "
            f"pairs = {per_element:g} k + {extra:g} for an integer k >= 1"
        )
    return int(elements)


def grading_ratio(length: float, elements: int, smallest: float) -> float:
    """Ratio for Refinement.graded whose smallest element is about ``smallest``.

    Solves ln(r) / (r - 1) = smallest * elements / length (the linear density of
    Refinement.breakpoints) by bisection on ln r: the left side falls monotonically from 1.
    """
    target = smallest * elements / length
    if target >= 1.0:
        return 1.0
    lo, hi = 1e-9, math.log(1e6)
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if mid / math.expm1(mid) > target else (lo, mid)
    return math.exp(0.5 * (lo + hi))


def hertz(scene: Scene, load: float | None = None) -> HertzLineContact | None:
    """Hertz contact of the scene's faces at P = ``load`` (the history's largest P by default)."""
    curvatures = [scene.pad.shape.curvature, scene.specimen.shape.curvature]
    if any(c is None for c in curvatures) or sum(curvatures) <= 0:
        return None
    pad, specimen = scene.pad.material, scene.specimen.material
    P = load if load is not None else max(scene.load.P)
    return HertzLineContact.from_bodies(
        load=P,
        radius_upper=1.0 / curvatures[0] if curvatures[0] else math.inf,
        radius_lower=1.0 / curvatures[1] if curvatures[1] else math.inf,
        E_upper=pad.E,
        nu_upper=pad.nu,
        E_lower=specimen.E,
        nu_lower=specimen.nu,
        plane_stress=pad.plane_stress and specimen.plane_stress,
    )


def zone_half_width(scene: Scene) -> float:
    """Half-width of the candidate contact zone in mm (from ``zone_width`` or ``zone`` x a)."""
    if scene.contact.zone_width is not None:
        return float(scene.contact.zone_width)
    contact = hertz(scene)
    if contact is None:
        raise SceneFileError(
            "the faces have no Hertz half-width to scale [contact] zone by (the pad's or the "
            "specimen's face is flat or user-drawn, shape = 'nurbs'); give the candidate zone "
            "in mm as [contact] zone_width"
        )
    zone = scene.contact.zone * contact.half_width
    if not (math.isfinite(zone) and zone > 1e-9 * _half_extent(scene.pad.shape)):
        raise SceneFileError(
            f"the Hertz half-width a = {contact.half_width:.3g} mm makes the candidate zone "
            f"([contact] zone x a = {zone:.3g} mm) vanish against the bodies; check the units "
            "of [material] E (MPa) and [load] P (N/mm), or give [contact] zone_width in mm"
        )
    return zone


def reference(scene: Scene):
    """The closed form the run is checked against, or (None, reason)."""
    pad, specimen = scene.pad.material, scene.specimen.material
    contact = hertz(scene)
    if contact is None:
        return None, "no Hertz contact (a flat or user-drawn face)"
    if pad.plane_stress != specimen.plane_stress:
        return None, "one body in plane stress, the other in plane strain"
    radius = min(1.0 / c for c in (scene.pad.shape.curvature, scene.specimen.shape.curvature) if c)
    if contact.half_width / radius > MAX_A_OVER_R:
        return None, (
            f"a / R = {contact.half_width / radius:.2g} is outside half-plane theory's validity "
            f"(a / R <= {MAX_A_OVER_R:g}: a contact small against the radius), so Hertz and "
            "Mindlin-Deresiewicz are not compared; the est columns give the discretisation "
            "error"
        )
    beta = dundurs_beta(pad.E, pad.nu, specimen.E, specimen.nu, plane_stress=pad.plane_stress)
    if abs(beta) > 1e-12:
        return None, f"dissimilar materials (Dundurs beta = {beta:.3g}) couple p and q"
    if len(set(scene.load.P)) > 1:
        return None, "P changes between steps (Hertz holds per step, the shear has no closed form)"
    if any(scene.load.bulk):
        nh = NowellHills(contact, scene.contact.friction)
        reason = nh.applies(scene.load.Q, scene.load.bulk)
        return (BulkPath(nh, scene.load.bulk), None) if reason is None else (None, reason)
    return MindlinDeresiewicz(contact, scene.contact.friction), None


@attrs.frozen
class BulkPath:
    """Nowell-Hills along the scene's bulk-stress path, read like Mindlin-Deresiewicz.

    The results ask a reference for ``shear_traction(x, history)`` with the Q values of
    the steps so far; the bulk stresses of the same steps come from the scene.
    """

    closed_form: NowellHills
    bulk: tuple[float, ...]

    @property
    def hertz(self) -> HertzLineContact:
        """The normal contact."""
        return self.closed_form.hertz

    @property
    def friction(self) -> float:
        """Coulomb coefficient f."""
        return self.closed_form.friction

    def shear_traction(self, x, history):
        """q(x) after the steps whose Q values are ``history``."""
        history = list(history)
        return self.closed_form.shear_traction(x, history, self.bulk[: len(history)])

    def stick_zone(self, history):
        """The current stick zone (e - c, e + c)."""
        history = list(history)
        return self.closed_form.stick_zone(history, self.bulk[: len(history)])


def refinements(scene: Scene, family: type[Basis], zone: float, pad: bool) -> dict:
    """Per-tag refinement: zone uniform, flanks graded toward it, sides/ends to corners."""
    contact = scene.contact
    body = scene.pad if pad else scene.specimen
    segments = [s for s in _face(scene, zone, pad) if s.tag == "contact"]
    if contact.pairs % len(segments):
        raise SceneFileError(
            f"the contact face has {len(segments)} segments, so [contact] pairs must be a "
            f"multiple of {len(segments)} (got {contact.pairs})"
        )
    k = zone_elements(family, contact.pairs // len(segments), contact.degree)
    zone_size = 2 * zone / (k * len(segments))
    corners = Refinement.graded(
        scene.mesh.side_elements, (0.0, 1.0), CORNER_RATIO, degree=contact.degree
    )
    levels = {
        "contact": Refinement(elements=k, degree=contact.degree),
        "top" if pad else "bottom": Refinement.graded(
            scene.mesh.top_elements, (0.0, 1.0), CORNER_RATIO, degree=contact.degree
        ),
    }
    half = _half_extent(body.shape)
    flank = grading_ratio(half - zone, scene.mesh.flank_elements, 2 * zone_size)
    near_zone = {"flank_left": 1.0, "flank_right": 0.0}  # the pad's face runs left to right
    if not pad:
        near_zone = {tag: 1.0 - end for tag, end in near_zone.items()}
    for tag, end in near_zone.items():
        levels[tag] = Refinement.graded(
            scene.mesh.flank_elements, end, flank, degree=contact.degree
        )
    tags = {s.tag for s in _face(scene, zone, pad)} | (
        {s.tag for s in body.shape.boundary(zone).segments} if pad else set()
    )
    for tag in ("side_left", "side_right", "end_left", "end_right"):
        if tag in tags:
            levels[tag] = corners
    return {tag: level for tag, level in levels.items() if tag in tags}


def _half_extent(shape) -> float:
    return (getattr(shape, "length", None) or shape.width) / 2


def _face(scene: Scene, zone: float, pad: bool):
    face = scene.pad.shape.face(zone)
    return face if pad else list(scene.specimen.shape.boundary(face, zone).segments)


def build(scene: Scene, **contact_overrides):
    """The Simulation of ``scene`` (``contact_overrides`` replace [contact] keys, e.g. pairs)."""
    if contact_overrides:
        scene = attrs.evolve(
            scene,
            contact=attrs.evolve(
                scene.contact, **{k: v for k, v in contact_overrides.items() if v is not None}
            ),
        )
    check_scene(scene)  # a hopeless size or history is refused with its estimate
    family = registry.get(scene.contact.basis)
    zone = zone_half_width(scene)
    pad = body_model(scene, "pad", family, zone, refinements(scene, family, zone, pad=True))
    specimen = body_model(
        scene, "specimen", family, zone, refinements(scene, family, zone, pad=False)
    )

    load = scene.load
    steps = tuple(
        LoadStep(name, P, Q, increments, loads={"bulk": bulk} if bulk or any(load.bulk) else {})
        for name, P, Q, bulk, increments in zip(
            load.steps, load.P, load.Q, load.bulk, load.increments, strict=True
        )
    )
    closed_form, reason = reference(scene)
    return Simulation(
        NodeToNodePair(pad, specimen),
        steps,
        solver=solver(scene.contact.solver),
        law=law(scene.contact.law, scene.contact.friction),
        reference=closed_form,
        name="scene",
    ), reason


def solver(name: str):
    """The contact solver a scene names (``[contact] solver``, a ``fretbem.solvers`` plugin)."""
    try:
        return registry.get(name, "solvers")()
    except registry.UnknownPluginError as err:
        raise SceneFileError(f"[contact] solver: {err}") from None


def law(name: str, friction: float):
    """The contact law a scene names (``[contact] law``), with the scene's friction."""
    try:
        return registry.get(name, "laws")(friction)
    except registry.UnknownPluginError as err:
        raise SceneFileError(f"[contact] law: {err}") from None


def body_model(scene: Scene, role: str, family: type[Basis], zone: float, refinement: dict):
    """The pad or the specimen as a body of its model (``bem`` or ``half-plane``)."""

    spec = getattr(scene, role)
    pad_face = scene.pad.shape.face(zone)
    bulk = any(scene.load.bulk)
    if role == "pad":
        conditions = [LoadingBlock("top")]
    elif spec.support == "ends":
        conditions = [
            Displacement("end_left", x=0.0, y=None),
            Displacement("bottom", x=None, y=0.0),
            Traction("end_right", x=1.0, y=0.0, load="bulk"),
        ]
    else:
        if bulk:
            raise SceneFileError(
                "[load] bulk is not zero but the specimen is clamped at its bottom "
                "([specimen] support = 'clamped-bottom'), so nothing carries a bulk stress; "
                "use a flat specimen with support = 'ends'"
            )
        conditions = [Displacement("bottom")]
    boundary = spec.shape.boundary(zone) if role == "pad" else spec.shape.boundary(pad_face, zone)
    try:
        model = registry.get(spec.model, "bodies")()
    except registry.UnknownPluginError as err:
        raise SceneFileError(f"[{role}] model: {err}") from None
    return model.build(scene, role, boundary, spec.material, conditions, family, refinement)
