"""Turn a :class:`~fretbem.scenes.spec.Scene` into a :class:`~fretbem.simulation.Simulation`.

The contact segment of each body holds exactly its ``pairs`` collocation points (the
``[contact]`` value, or the body's own ``pairs`` or ``elements``: faces that differ are
paired by projection, ``[contact] pairing = "node-to-segment"``); the flanks are graded
toward the zone, sides and ends toward their corners (where the traction is singular).
The closed-form reference is chosen from the scene: Mindlin-Deresiewicz without bulk
stress, Nowell-Hills with sigma_B in phase with Q, none where neither applies (the reason
is kept for the report).
"""

from __future__ import annotations

import functools
import math

import attrs

from fretbem import registry
from fretbem.basis import Basis, Refinement, points_per_element
from fretbem.conditions import Displacement, LoadingBlock, Traction
from fretbem.contact.control import Rig
from fretbem.geometry.boundary import OpenFace
from fretbem.geometry.shapes import (
    CylinderPad,
    CylinderSpecimen,
    FlatSpecimen,
    GrooveSpecimen,
    RoundedFlatPad,
)
from fretbem.simulation import LoadStep, Simulation
from fretbem.verification.closed_forms import (
    HertzLineContact,
    MindlinDeresiewicz,
    SlidingPath,
    dundurs_beta,
)
from fretbem.verification.nowell_hills import NowellHills

from .limits import check_scene
from .spec import Scene, SceneFileError, check_frame, check_groove
from .track import sliding_scene, track_face, track_half_width

__all__ = [
    "CORNER_RATIO",
    "FaceDiscretisation",
    "build",
    "faces_differ",
    "grading_ratio",
    "hertz",
    "reference",
    "zone_elements",
]

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


@functools.lru_cache(maxsize=64)
def grading_ratio(length: float, elements: int, smallest: float) -> float:
    """Ratio for Refinement.graded whose smallest element is about ``smallest``.

    Solves ln(r) / (r - 1) = smallest * elements / length (the linear density of
    Refinement.breakpoints) by bisection on ln r: the left side falls monotonically from 1.
    Kept per arguments: the pad and the specimen of a scene usually ask the same (about 55
    Python steps each).
    """
    target = smallest * elements / length
    if target >= 1.0:
        return 1.0
    lo, hi = 1e-9, math.log(1e6)
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):  # lo and hi adjacent floats: no later step moves either
            break
        lo, hi = (mid, hi) if mid / math.expm1(mid) > target else (lo, mid)
    return math.exp(0.5 * (lo + hi))


def hertz(scene: Scene, load: float | None = None) -> HertzLineContact | None:
    """Hertz contact of the scene's faces at P = ``load`` (the history's largest P by default)."""
    curvatures = [scene.pad.shape.curvature, scene.specimen.shape.curvature]
    if any(c is None for c in curvatures) or sum(curvatures) <= 0:
        return None
    if load is None and scene.load.approach is not None:
        return None  # the approach is imposed: P is an output
    pad, specimen = scene.pad.material, scene.specimen.material
    P = load if load is not None else max(scene.load.P)
    if curvatures[1] < 0:  # a groove: conforming, 1/R* = 1/R_pad - 1/R_groove, on the pad
        curvatures = [sum(curvatures), 0.0]
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
    if scene.load.approach is not None:
        raise SceneFileError(
            "[load] approach imposes the normal approach, so P (and the Hertz half-width that "
            "[contact] zone scales) is not known before the run; give the candidate zone in "
            "mm as [contact] zone_width"
        )
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
    if scene.load.approach is not None:
        return None, "the normal approach is imposed (P is an output of the run)"
    if scene.block_rotates:
        return None, (
            "the pad's block rotates (a [load] moment or rotation, or [rig] "
            "stiffness_rotation): the contact shifts with the tilt, which the centred closed "
            "forms do not follow (docs/verification/tilted_pad.py compares the shifted ones)"
        )
    contact = hertz(scene)
    if contact is None:
        return None, "no Hertz contact (a flat or user-drawn face)"
    if pad.plane_stress != specimen.plane_stress:
        return None, "one body in plane stress, the other in plane strain"
    curvatures = (scene.pad.shape.curvature, scene.specimen.shape.curvature)
    radius = min(1.0 / abs(c) for c in curvatures if c)  # a groove's curvature is negative
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
    if scene.load.delta is not None:
        if any(scene.load.bulk):
            return None, "the tangential displacement is imposed with a bulk stress"
        return SlidingPath(MindlinDeresiewicz(contact, scene.contact.friction)), None
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


@attrs.frozen
class FaceDiscretisation:
    """One body's contact-face discretisation: its own keys over the ``[contact]`` defaults.

    ``pairs`` and ``elements`` come from the body's table (``[pad]``, ``[specimen]``) or
    ``[contact] pairs``; ``where`` names the key that set the count, for messages.
    """

    basis: str
    degree: int | None
    pairs: int | None
    elements: int | None
    where: str

    @classmethod
    def of(cls, scene: Scene, role: str) -> FaceDiscretisation:
        """The face of ``role`` ("pad" or "specimen")."""
        body, contact = getattr(scene, role), scene.contact
        own = body.pairs is not None or body.elements is not None
        return cls(
            basis=body.basis or contact.basis,
            degree=body.degree if body.degree is not None else contact.degree,
            pairs=body.pairs if own else contact.pairs,
            elements=body.elements,
            where=f"[{role}] {'elements' if body.elements is not None else 'pairs'}"
            if own
            else "[contact] pairs",
        )


def refinements(
    scene: Scene, family: type[Basis], zone: float, pad: bool, whole: bool = True
) -> dict:
    """Per-tag refinement: zone uniform, flanks graded toward it, sides/ends to corners
    (``whole`` False: the face's tags only, for a body built from its face alone)."""
    body = scene.pad if pad else scene.specimen
    face = FaceDiscretisation.of(scene, "pad" if pad else "specimen")
    degree = face.degree
    face_segments = _face(scene, zone, pad, whole)
    segments = [s for s in face_segments if s.tag == "contact"]
    if face.elements is not None:
        k = face.elements
    else:
        if face.pairs % len(segments):
            raise SceneFileError(
                f"the contact face has {len(segments)} segments, so {face.where} must be a "
                f"multiple of {len(segments)} (got {face.pairs})"
            )
        try:
            k = zone_elements(family, face.pairs // len(segments), degree)
        except ValueError as err:
            raise SceneFileError(f"{face.where}: {err}") from None
    zone_size = 2 * zone / (k * len(segments))
    tags = {s.tag for s in face_segments} | (
        {s.tag for s in _geometry(body.shape, "boundary", zone).segments}
        if pad and whole
        else set()
    )
    # only the levels of the tags the body has (a face-only body: its contact alone)
    levels = {"contact": Refinement(elements=k, degree=degree)}
    ends = "top" if pad else "bottom"
    if ends in tags:
        levels[ends] = Refinement.graded(
            scene.mesh.top_elements, (0.0, 1.0), CORNER_RATIO, degree=degree
        )
    near_zone = {"flank_left": 1.0, "flank_right": 0.0}  # the pad's face runs left to right
    if not pad:
        near_zone = {tag: 1.0 - end for tag, end in near_zone.items()}
    if tags & near_zone.keys():
        half = _half_extent(body.shape)
        flank = grading_ratio(half - zone, scene.mesh.flank_elements, 2 * zone_size)
        for tag, end in near_zone.items():
            levels[tag] = Refinement.graded(scene.mesh.flank_elements, end, flank, degree=degree)
    corner_tags = [t for t in ("side_left", "side_right", "end_left", "end_right") if t in tags]
    if corner_tags:
        corners = Refinement.graded(
            scene.mesh.side_elements, (0.0, 1.0), CORNER_RATIO, degree=degree
        )
        for tag in corner_tags:
            levels[tag] = corners
    return {tag: level for tag, level in levels.items() if tag in tags}


def _half_extent(shape) -> float:
    return (getattr(shape, "length", None) or shape.width) / 2


def _pad_face(scene: Scene, zone: float, pad: bool):
    """The pad's face at ``zone``; for the specimen of a sliding scene, its track."""
    if scene.contact.sliding and not pad:
        return track_face(zone, scene.specimen.shape)
    return list(_geometry(scene.pad.shape, "face", zone))


def _face(scene: Scene, zone: float, pad: bool, whole: bool = True):
    """The pad's face, or the specimen's boundary segments (its face alone if not ``whole``)."""
    face = _pad_face(scene, zone, pad)
    if pad:
        return face
    if not whole:
        return list(_geometry(scene.specimen.shape, "face", tuple(face), zone))
    return list(_specimen_boundary(scene, face, zone).segments)


#: the shapes whose own checks make their closed boundary valid (a drawn ``nurbs`` shape is
#: checked as a boundary only)
_LIBRARY_PADS = (CylinderPad, RoundedFlatPad)
_LIBRARY_SPECIMENS = (FlatSpecimen, CylinderSpecimen, GrooveSpecimen)


def _whole(scene: Scene, model) -> bool:
    """Whether a body of ``model`` is built on its closed boundary: every model but one that
    reads only its face (:attr:`~fretbem.scenes.models.BodyModel.face_only`) between two
    library shapes. A drawn shape's boundary is always built and checked, and so is a
    library specimen's facing a drawn pad (its flanks run to the pad's contact ends)."""
    library = isinstance(scene.pad.shape, _LIBRARY_PADS) and isinstance(
        scene.specimen.shape, _LIBRARY_SPECIMENS
    )
    return not (model.face_only and library)


def _specimen_boundary(scene: Scene, pad_face, zone: float):
    return _geometry(scene.specimen.shape, "boundary", tuple(pad_face), zone)


def _geometry(shape, method: str, *args):
    """``shape.method(*args)``, kept for the shape and arguments (see :func:`_built`)."""
    try:
        return _built(shape, method, *args)
    except TypeError:  # a shape with unhashable fields: build it each time
        return _call(shape, method, *args)


def _call(shape, method: str, *args):
    if method == "face":
        return tuple(shape.face(*args))
    if method == "boundary" and len(args) == 2:  # a specimen: the pad's face, the zone
        return shape.boundary(list(args[0]), args[1])
    if method == "boundary" and isinstance(shape, CylinderPad | RoundedFlatPad):
        # a library pad: its face as built for the scene (the same segments), and its sides
        return shape.boundary(*args, face=_geometry(shape, "face", *args))
    return getattr(shape, method)(*args)


#: a scene build asks for each body's face and boundary four or five times, and a sweep or
#: study builds the same shapes again for every case: they are built and checked once per
#: (shape, arguments). Shapes, segments and boundaries are frozen; a specimen's key holds the
#: pad's face segments themselves, which this cache hands out the same each time
_built = functools.lru_cache(maxsize=64)(_call)


def build(scene: Scene, *, name: str = "scene", **contact_overrides):
    """The Simulation of ``scene``, named ``name`` (``contact_overrides`` replace [contact]
    keys, e.g. pairs)."""
    overrides = {k: v for k, v in contact_overrides.items() if v is not None}
    if overrides:
        scene = attrs.evolve(scene, contact=attrs.evolve(scene.contact, **overrides))
    if "pairs" in overrides:  # a pair count given for the run sets every face's
        scene = _faces_at(scene, overrides["pairs"])
    check_scene(scene)  # a hopeless size or history is refused with its estimate
    if isinstance(scene.specimen.shape, GrooveSpecimen):  # a Scene made in Python too
        check_groove(scene.pad.shape, scene.specimen.shape, scene.contact.pairing)
    check_frame(scene.contact.frame, scene.contact.sliding, scene.specimen.shape)
    zone = zone_half_width(scene)
    pad_family = _family(scene, "pad")
    specimen_family = _family(scene, "specimen")
    _check_pairing(scene)
    if isinstance(scene.specimen.shape, GrooveSpecimen):  # a drawn pad must fit in it
        scene.specimen.shape.check_pad(_pad_face(scene, zone, True))
    pad_model, specimen_model = _model(scene, "pad"), _model(scene, "specimen")
    pad_whole = _whole(scene, pad_model)
    pad_levels = refinements(scene, pad_family, zone, pad=True, whole=pad_whole)
    specimen_zone = zone
    if scene.contact.sliding:  # the specimen's contact segment covers the whole slide
        specimen_zone = track_half_width(scene, zone)
        pad_elements = pad_levels["contact"].elements * len(
            [s for s in _face(scene, zone, True) if s.tag == "contact"]
        )
        own = scene.specimen.pairs is not None or scene.specimen.elements is not None
        specimen_elements = (  # [specimen] pairs or elements: a density in the zone
            refinements(scene, specimen_family, zone, False, _whole(scene, specimen_model))[
                "contact"
            ].elements
            if own
            else None
        )
        scene = sliding_scene(scene, zone, specimen_zone, pad_elements, specimen_elements)
    pad = body_model(scene, "pad", pad_family, zone, pad_levels, pad_model)
    specimen_whole = _whole(scene, specimen_model)
    specimen = body_model(
        scene,
        "specimen",
        specimen_family,
        specimen_zone,
        refinements(scene, specimen_family, specimen_zone, False, specimen_whole),
        specimen_model,
    )

    steps = load_steps(scene.load)
    closed_form, reason = reference(scene)
    # finite sliding stands its pairs on the pad's nodes, which move with the pad and stay
    # faced by the longer track, whichever face has fewer nodes
    sides = {"slave": "upper"} if scene.contact.sliding else {}
    return Simulation(
        pairing(scene.contact.pairing)(pad, specimen, **sides),
        steps,
        solver=solver(scene.contact.solver),
        law=law(scene.contact.law, scene.contact.friction),
        reference=closed_form,
        name=name,
        rig=rig(scene),
    ), reason


def _family(scene: Scene, role: str) -> type[Basis]:
    """The basis family of a body (its own ``basis`` key or ``[contact] basis``)."""
    return registry.get(FaceDiscretisation.of(scene, role).basis)


def _faces_at(scene: Scene, pairs: int) -> Scene:
    """Every face at ``pairs`` collocation points (at most, for a family that cannot hit it
    exactly when the faces differ): a run-wide pair count over the per-face keys."""
    out = {}
    for role in ("pad", "specimen"):
        spec = getattr(scene, role)
        if spec.pairs is None and spec.elements is None:
            continue
        family = _family(scene, role)
        face = FaceDiscretisation.of(scene, role)
        try:
            zone_elements(family, pairs, face.degree)
            out[role] = attrs.evolve(spec, pairs=pairs, elements=None)
        except ValueError:
            per, extra = points_per_element(family, face.degree)
            out[role] = attrs.evolve(
                spec, pairs=None, elements=max(1, math.floor((pairs - extra) / per))
            )
    return attrs.evolve(scene, **out) if out else scene


def faces_differ(scene: Scene) -> list[str]:
    """The face keys whose values differ between pad and specimen (empty: faces alike)."""
    pad, specimen = (FaceDiscretisation.of(scene, r) for r in ("pad", "specimen"))
    return [
        name
        for name in ("basis", "degree", "pairs", "elements")
        if getattr(pad, name) != getattr(specimen, name)
    ]


def _check_pairing(scene: Scene) -> None:
    """Faces discretised differently need a pairing by projection: say so, naming the keys."""
    differ = faces_differ(scene)
    if differ and scene.contact.pairing == "node-to-node":
        pad, specimen = (FaceDiscretisation.of(scene, r) for r in ("pad", "specimen"))
        shown = ", ".join(
            f"{name} {getattr(pad, name)!r} vs {getattr(specimen, name)!r}" for name in differ
        )
        raise SceneFileError(
            f"the pad and specimen contact faces are discretised differently ({shown}; "
            "[pad] and [specimen] keys over [contact]), but [contact] pairing = "
            "'node-to-node' needs them alike; set [contact] pairing = 'node-to-segment', "
            "or give both faces the same keys"
        )


def pairing(name: str):
    """The contact pair class a scene names (``[contact] pairing``, a ``fretbem.pairings``
    plugin)."""
    try:
        return registry.get(name, "pairings")
    except registry.UnknownPluginError as err:
        raise SceneFileError(f"[contact] pairing: {err}") from None


def rig(scene: Scene) -> Rig:
    """The rig springs of a scene's [rig] table (rigid where a stiffness is not given)."""
    spec = getattr(scene, "rig", None)
    if spec is None:
        return Rig()
    return Rig(
        tangential=math.inf if spec.stiffness_x is None else spec.stiffness_x,
        normal=math.inf if spec.stiffness_y is None else spec.stiffness_y,
        rotational=math.inf if spec.stiffness_rotation is None else spec.stiffness_rotation,
        pivot_height=spec.pivot_height,
    )


def load_steps(load) -> tuple[LoadStep, ...]:
    """The LoadSteps of a scene's [load] table (forces, or block displacements where given)."""
    n = len(load.steps)
    deltas = load.delta or (None,) * n
    approaches = load.approach or (None,) * n
    cycles = load.cycle or (0,) * n
    moments = getattr(load, "moment", None) or (None,) * n
    rotations = getattr(load, "rotation", None) or (None,) * n
    return tuple(
        LoadStep(
            name, P, Q, increments, loads={"bulk": bulk} if bulk or any(load.bulk) else {},
            delta=delta, approach=approach, cycle=cycle, moment=moment, rotation=rotation,
        )
        for name, P, Q, bulk, increments, delta, approach, cycle, moment, rotation in zip(
            load.steps, load.P, load.Q, load.bulk, load.increments, deltas, approaches, cycles,
            moments, rotations, strict=True,
        )
    )  # fmt: skip


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


def _model(scene: Scene, role: str):
    """The body model (a ``fretbem.bodies`` plugin) the pad or the specimen names."""
    try:
        return registry.get(getattr(scene, role).model, "bodies")()
    except registry.UnknownPluginError as err:
        raise SceneFileError(f"[{role}] model: {err}") from None


def body_model(
    scene: Scene, role: str, family: type[Basis], zone: float, refinement: dict, model=None
):
    """The pad or the specimen as a body of its model (``bem`` or ``half-plane``; ``model``,
    the plugin's instance, if already found). A model that reads only its face gets it as
    an :class:`~fretbem.geometry.boundary.OpenFace` between library shapes (:func:`_whole`)."""

    spec = getattr(scene, role)
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
    model = _model(scene, role) if model is None else model
    if not _whole(scene, model):
        boundary = OpenFace(_face(scene, zone, role == "pad", whole=False))
    elif role == "pad":
        boundary = _geometry(spec.shape, "boundary", zone)
    else:
        boundary = _specimen_boundary(scene, _pad_face(scene, zone, False), zone)
    return model.build(scene, role, boundary, spec.material, conditions, family, refinement)
