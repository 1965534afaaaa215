"""A clear error for every bad input of issue 5, at the level a user meets it.

Each test asserts the error type and that the message names the cause (and, where there
is one, the fix). The list follows the issue: knots, weights, degree, boundaries, tags,
rigid motion, contact pairing, overlap, friction, material constants, load history, scene
files and basis families. Nothing here assembles a BEM matrix.
"""

from __future__ import annotations

import attrs
import numpy as np
import pytest

from fretbem.bem.body import BemBody
from fretbem.body import RigidMotionError
from fretbem.conditions import Displacement, LoadingBlock, Traction
from fretbem.contact.law import CoulombFriction
from fretbem.contact.pairs import ContactDiscretisationError, NodeToNodePair
from fretbem.geometry.boundary import Boundary, BoundaryError, Segment
from fretbem.geometry.knots import KnotVectorError
from fretbem.geometry.nurbs import NurbsCurve
from fretbem.material import Material
from fretbem.registry import UnknownBasisError
from fretbem.scenes.builder import build
from fretbem.scenes.file import SceneFileError, load_scene, scene_from_data
from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.simulation import GrossSlidingError, LoadHistoryError, LoadStep, Simulation, run

RECTANGLE = Boundary.polygon([[0, 0], [2, 0], [2, 1], [0, 1]], ["bottom", "right", "top", "left"])
STEEL = Material(210000.0, 0.3)


@pytest.fixture(scope="module")
def reference():
    """The reference scene (21 pairs), built but never assembled."""
    return cattaneo_mindlin(pairs=21)


def moved(body: BemBody, shift, **changes) -> BemBody:
    """The same body translated by ``shift`` (conditions and mesh unchanged)."""
    boundary = Boundary(
        [
            Segment(s.tag, attrs.evolve(s.curve, control_points=s.curve.control_points + shift))
            for s in body.boundary.segments
        ]
    )
    return attrs.evolve(body, boundary=boundary, **changes)


# ---------------------------------------------------------------------------- NURBS


@pytest.mark.parametrize(
    ("knots", "points", "match"),
    [
        ([0, 0, 0, 0.7, 0.3, 1, 1, 1], 5, r"non-decreasing, but knot 4 \(0\.3\) < knot 3 \(0\.7\)"),
        ([0, 0, 0, 0.5, 1, 1, 1], 5, r"7 entries but degree 2 with 5 control points needs"),
        ([0, 0, 0, 0.5, 1, 1, 1, 1, 1], 5, r"9 entries .* n \+ p \+ 1 = 8"),
    ],
    ids=["decreasing", "too-short", "too-long"],
)
def test_bad_knot_vector(knots, points, match):
    with pytest.raises(KnotVectorError, match=match):
        NurbsCurve(2, knots, np.zeros((points, 2)), np.ones(points))


@pytest.mark.parametrize("weight", [0.0, -1.0])
def test_non_positive_weight(weight):
    with pytest.raises(ValueError, match=rf"NURBS weight 1 is {weight}; weights must be > 0"):
        NurbsCurve(2, [0, 0, 0, 1, 1, 1], [[0, 0], [1, 1], [2, 0]], [1.0, weight, 1.0])


@pytest.mark.parametrize("degree", [0, -2])
def test_degree_below_one(degree):
    with pytest.raises(KnotVectorError, match=rf"degree must be an integer >= 1, got {degree}"):
        NurbsCurve(degree, [0, 0, 1, 1], [[0, 0], [1, 0]], [1, 1])


def test_non_finite_curve_data():
    with pytest.raises(ValueError, match=r"NurbsCurve\.control_points must be finite"):
        NurbsCurve(1, [0, 0, 1, 1], [[0, 0], [np.inf, 1]], [1, 1])
    with pytest.raises(ValueError, match=r"NurbsCurve\.weights must be finite"):
        NurbsCurve(1, [0, 0, 1, 1], [[0, 0], [1, 1]], [1, np.nan])


# ---------------------------------------------------------------------------- boundaries


def test_boundary_not_closed():
    segments = [
        Segment("a", NurbsCurve.line([0, 0], [1, 0])),
        Segment("b", NurbsCurve.line([1, 0], [1, 1])),
        Segment("c", NurbsCurve.line([1, 1], [0, 0.2])),
    ]
    with pytest.raises(BoundaryError, match=r"not closed: segment 2 \('c'\) ends at .*gap 0\.2"):
        Boundary(segments)


def test_boundary_self_crossing():
    with pytest.raises(BoundaryError, match=r"crosses itself: segments 0 \('a'\) and 2 \('c'\)"):
        Boundary.polygon([[0, 0], [1, 1], [1, 0], [0, 1]], ["a", "b", "c", "d"])


def test_boundary_clockwise():
    with pytest.raises(BoundaryError, match=r"runs clockwise .*counter-clockwise"):
        Boundary.polygon([[0, 0], [0, 1], [1, 1], [1, 0]], ["a", "b", "c", "d"])


def test_zero_length_segment():
    with pytest.raises(BoundaryError, match=r"segment 1 \('b'\) has zero length"):
        Boundary.polygon([[0, 0], [1, 0], [1, 0], [1, 1], [0, 1]], ["a", "b", "c", "d", "e"])


# ---------------------------------------------------------------------------- tags


@pytest.mark.parametrize(
    ("condition", "used_by"),
    [
        (Displacement("roof"), "a Displacement condition"),
        (Traction("roof", y=-1.0), "a Traction condition"),
        (LoadingBlock("roof", (0.0, -1.0)), "a LoadingBlock condition"),
    ],
)
def test_condition_on_missing_tag(condition, used_by):
    with pytest.raises(
        KeyError,
        match=rf"{used_by} refers to tag 'roof', but no boundary "
        r"segment is tagged 'roof'; the tags are \['bottom', 'left'",
    ):
        BemBody(RECTANGLE, STEEL, [Displacement("bottom"), condition])


def test_refinement_on_missing_tag():
    from fretbem.basis import Refinement

    with pytest.raises(KeyError, match=r"a refinement refers to tag 'roof'"):
        BemBody(RECTANGLE, STEEL, [Displacement("bottom")], refinement={"roof": Refinement(3)})


@pytest.mark.parametrize("side", ["upper_tag", "lower_tag"])
def test_contact_pair_on_missing_tag(reference, side):
    pair = reference.pair
    with pytest.raises(KeyError, match=r"the contact pair refers to tag 'contcat', but no"):
        NodeToNodePair(pair.upper, pair.lower, **{side: "contcat"})


# ---------------------------------------------------------------------------- rigid motion


def test_body_with_free_rigid_motion():
    body = BemBody(RECTANGLE, STEEL, [Traction("right", x=1.0), Traction("left", x=-1.0)])
    with pytest.raises(
        RigidMotionError,
        match=r"rigid motion free \(rotation, x translation, "
        r"y translation\).*prescribe a displacement",
    ):
        body.solve()


def test_contact_body_with_free_rigid_motion(reference):
    """A lower body held by nothing but tractions cannot carry the pad: named before solving."""
    lower = attrs.evolve(reference.pair.lower, conditions=[Traction("bottom", y=100.0 / 6.5)])
    pair = NodeToNodePair(reference.pair.upper, lower)
    with pytest.raises(RigidMotionError, match=r"body 'specimen'.* rigid motion free \("):
        pair.condensed()
    assert lower.timings == {}  # refused before the assembly


# ---------------------------------------------------------------------------- contact pairs


def test_contact_segments_that_face_away(reference):
    """A pad whose 'contact' segment is its top face, placed above the specimen, would
    'touch' through its own body after a rigid translation; it is refused."""
    lower = reference.pair.lower
    pad = moved(
        lower, [0.0, 40.0], conditions=[LoadingBlock("bottom", (0.0, -100.0))], name="upper"
    )
    pair = NodeToNodePair(pad, lower)
    match = r"do not face each other: at \[ ?0\.? +40\.?\] the outward normal of the upper"
    with pytest.raises(ContactDiscretisationError, match=match + " segment 'contact'"):
        _ = pair.pairing()


def test_contact_segments_that_do_not_face_along_the_surface(reference):
    """The pad shifted sideways by half a pair spacing: no lower point has a partner."""
    upper = moved(reference.pair.upper, [0.01, 0.0])
    with pytest.raises(
        ContactDiscretisationError,
        match=r"has no facing point on the upper "
        r"segment 'contact'.*discretisations must match",
    ):
        _ = NodeToNodePair(upper, reference.pair.lower).pairing()


def test_contact_discretisations_that_do_not_match(reference):
    other = cattaneo_mindlin(pairs=23).pair.upper
    with pytest.raises(
        ContactDiscretisationError,
        match=r"the lower segment 'contact' has 21 "
        r"collocation points but the upper 'contact' has 23",
    ):
        _ = NodeToNodePair(other, reference.pair.lower).pairing()


def test_bodies_that_overlap_at_the_start(reference):
    upper = moved(reference.pair.upper, [0.0, -0.001])
    with pytest.raises(ContactDiscretisationError, match=r"overlap at the start by 0\.001"):
        _ = NodeToNodePair(upper, reference.pair.lower).pairing()


# ---------------------------------------------------------------------------- friction


@pytest.mark.parametrize("friction", [-0.1, np.nan])
def test_bad_friction(reference, friction):
    with pytest.raises(ValueError, match=r"CoulombFriction\.friction must be (>= 0|finite)"):
        CoulombFriction(friction)
    with pytest.raises(ValueError, match=r"friction must be (>= 0|finite)"):
        cattaneo_mindlin(pairs=21, friction=friction)


def test_frictionless_contact_under_force_control(reference):
    """f = 0 is a valid coefficient, but nothing then holds the pad tangentially."""
    pair = NodeToNodePair(reference.pair.upper, reference.pair.lower)
    with pytest.raises(GrossSlidingError, match=r"frictionless \(f = 0\).* undetermined"):
        Simulation(pair, [LoadStep("A", 100.0, 0.0)], law=CoulombFriction(0.0))


# ---------------------------------------------------------------------------- material


@pytest.mark.parametrize("modulus", [0.0, -73400.0])
def test_non_positive_modulus(modulus):
    with pytest.raises(ValueError, match=rf"Material\.E must be > 0, got {modulus}"):
        Material(modulus, 0.3)
    # the scene names the body's field
    with pytest.raises(ValueError, match=rf"E_lower must be > 0, got {modulus}"):
        cattaneo_mindlin(pairs=21, E_lower=modulus)


@pytest.mark.parametrize("nu", [0.5, 0.7, -1.0, -1.5, np.nan])
def test_poisson_ratio_outside_its_range(nu):
    with pytest.raises(ValueError, match=r"Poisson's ratio nu must lie in \(-1, 0\.5\)"):
        Material(73400.0, nu)
    with pytest.raises(
        ValueError,
        match=r"CattaneoMindlinScene\.nu_upper: Poisson's ratio nu must lie in \(-1, 0\.5\)",
    ):
        cattaneo_mindlin(pairs=21, nu_upper=nu)


# ---------------------------------------------------------------------------- load history


@pytest.mark.parametrize(
    "steps",
    [
        [LoadStep("A", 100.0, 5.0)],
        [LoadStep("A", 0.0, 0.0), LoadStep("B", 100.0, 0.0)],
        [LoadStep("A", -100.0, 0.0)],
    ],
    ids=["tangential-first", "zero-P-first", "tension-first"],
)
def test_first_step_is_not_a_normal_load(reference, steps):
    with pytest.raises(
        LoadHistoryError,
        match=r"first load step \('A'.*\) must be a pure "
        r"normal load, P > 0 and Q = 0",
    ):
        Simulation(reference.pair, steps, law=reference.law)


def test_later_step_releases_the_contact(reference):
    steps = [LoadStep("A", 100.0, 0.0), LoadStep("lift", -5.0, 0.0)]
    with pytest.raises(
        LoadHistoryError,
        match=r"load step 'lift' has P = -5\.0; the bodies "
        r"must stay pressed together",
    ):
        Simulation(reference.pair, steps, law=reference.law)


def test_empty_history(reference):
    with pytest.raises(LoadHistoryError, match="at least one load step"):
        Simulation(reference.pair, [], law=reference.law)


def test_scene_history_starting_with_shear():
    with pytest.raises(LoadHistoryError, match=r"first load step \('A': P = 100\.0, Q = 5\.0\)"):
        cattaneo_mindlin(pairs=21, tangential=(5.0, 0.0), names=("A", "B"))


@pytest.mark.parametrize("value", [np.nan, np.inf])
def test_non_finite_load(value):
    with pytest.raises(ValueError, match=r"LoadStep\.(normal|tangential) must be finite"):
        LoadStep("A", value, 0.0)
    with pytest.raises(ValueError, match=r"LoadStep\.tangential must be finite"):
        LoadStep("A", 100.0, value)


def test_newton_failure_says_what_to_change(reference):
    """A Newton iteration that cannot converge carries its history and suggests fixes."""
    from fretbem.solvers.newton import NewtonConvergenceError, SemiSmoothNewton

    strict = Simulation(
        reference.pair,
        reference.steps,
        SemiSmoothNewton(max_iterations=1, max_substeps=0),
        law=reference.law,
    )
    match = r"did not converge in 1 iterations .*pairs \[.*\] kept changing state .*"
    with pytest.raises(
        NewtonConvergenceError, match=match + "sub-increments.*max_substeps.*refine"
    ):
        run(strict)


def test_zone_larger_than_the_face():
    match = r"candidate zone half-width 3\.289 mm must lie inside the face \(half-width 3\.25"
    with pytest.raises(ValueError, match=match + r" mm\); lower 'zone' or widen the bodies"):
        cattaneo_mindlin(pairs=21, zone=10.0)


# ---------------------------------------------------------------------------- scene files

NON_FINITE = [
    ("[scene]\nzone = nan", r"\[scene\] zone must be a finite number, got nan"),
    ("[geometry]\nradius = inf", r"\[geometry\] radius must be a finite number, got inf"),
    ("[geometry]\nwidth = -inf", r"\[geometry\] width must be a finite number, got -inf"),
    ("[geometry]\nheight = nan", r"\[geometry\] height must be a finite number"),
    ("[material]\nE = nan", r"\[material\] E must be a finite number, got nan"),
    ("[material]\nnu = inf", r"\[material\] nu must be a finite number, got inf"),
    ("[material.upper]\nE = inf", r"\[material\.upper\] E must be a finite number"),
    ("[material.lower]\nnu = -nan", r"\[material\.lower\] nu must be a finite number"),
    ("[contact]\nfriction = nan", r"\[contact\] friction must be a finite number"),
    ("[load]\nP = inf", r"\[load\] P must be a finite number, got inf"),
    ("[load]\nQ = [0.0, 18.0, nan]", r"\[load\] Q\[2\] must be a finite number, got nan"),
]


@pytest.mark.parametrize(("text", "match"), NON_FINITE)
def test_scene_file_with_non_finite_number(tmp_path, text, match):
    path = tmp_path / "scene.toml"
    path.write_text(text + "\n")
    with pytest.raises(SceneFileError, match=rf"scene\.toml: {match}"):
        load_scene(path)


UNKNOWN = [
    ("[scene]\npair = 61", r"unknown key \['pair'\] in \[scene\]; the keys there are \['basis'"),
    ("[geometry]\nradious = 70.0", r"unknown key \['radious'\] in \[geometry\]"),
    ("[mesh]\nflank = 3", r"unknown key \['flank'\] in \[mesh\]"),
    ("[material]\nYoung = 1.0", r"unknown key \['Young'\] in \[material\]"),
    ("[material.upper]\nG = 1.0", r"unknown key \['G'\] in \[material\.upper\]"),
    ("[material.middle]\nE = 1.0", r"unknown key \['middle'\] in \[material\]"),
    ("[contact]\nmu = 0.3", r"unknown key \['mu'\] in \[contact\]"),
    ("[load]\nq = [0.0]", r"unknown key \['q'\] in \[load\]"),
    ("[loads]\nP = 100.0", r"unknown key \['loads'\] in the scene file"),
    ("basis = 'nurbs'", r"unknown key \['basis'\] in the scene file"),
    ("[scene]\nincrement = 2\nbasis_ = 'x'", r"unknown keys \['basis_', 'increment'\] in "),
]


@pytest.mark.parametrize(("text", "match"), UNKNOWN)
def test_scene_file_with_unknown_key(tmp_path, text, match):
    path = tmp_path / "scene.toml"
    path.write_text(text + "\n")
    with pytest.raises(SceneFileError, match=match):
        load_scene(path)


def test_scene_file_material_override_is_not_a_table():
    with pytest.raises(SceneFileError, match=r"\[material\.upper\] must be a table"):
        scene_from_data({"material": {"upper": 3}})


def test_scene_file_semantic_errors_name_the_cause():
    """Values of the right type but outside their range fail when read or built."""
    with pytest.raises(ValueError, match=r"friction must be > 0.*got -0\.1"):
        build(scene_from_data({"contact": {"friction": -0.1}}))
    with pytest.raises(GrossSlidingError, match=r"\|Q\| = 40 >= f P = 30"):
        build(scene_from_data({"load": {"Q": [0.0, 40.0]}}))


# ---------------------------------------------------------------------------- basis family


def test_basis_family_not_installed(tmp_path):
    message = r"unknown basis family 'quartic'; installed families: .*'lagrange2'.*'nurbs'"
    with pytest.raises(UnknownBasisError, match=message):
        BemBody(RECTANGLE, STEEL, [Displacement("bottom")], basis="quartic")
    with pytest.raises(UnknownBasisError, match=message):
        cattaneo_mindlin(pairs=21, basis="quartic")
    path = tmp_path / "scene.toml"
    path.write_text("[contact]\nbasis = 'quartic'\n")
    with pytest.raises(UnknownBasisError, match=message):
        build(load_scene(path))
