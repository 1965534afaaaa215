"""Finite sliding along an arc: the reference scene's cylinder pad (R = 70 mm, 6.5 x 16.25
mm, held by its block) dragged in gross slip along a convex cylindrical BEM specimen of the
same radius and material (12 x 10 mm, clamped at its bottom), three contact widths along
the arc and back (examples/gross_sliding_arc.toml).

The pad turns about the arc's centre by s / R as it slides, so it stays on the arc and
normal to it; P acts along the local normal, Q along the local tangent. Checked, as on the
flat (tests/validation/test_sliding_bem.py): the sliding run against the same bodies solved
without sliding with the pad placed (turned) where it slid, to round-off; against Hertz
with 1/R* = 1/R_pad + 1/R_specimen, the pressure no farther from it on the track than at
the start (the finite bodies' own difference); q = f p at every pair in contact and Q = f P
in the local frame, then reversing; the pad's turn against the distance its face slid. The
turned pad's condensation is checked exactly against a specimen drawn turned the other way.
Tolerances: measured values (in the comments) plus a margin.
"""

from __future__ import annotations

import copy
import math
from pathlib import Path

import attrs
import numpy as np
import pytest
import tomllib

from fretbem.geometry.boundary import Segment
from fretbem.geometry.nurbs import NurbsCurve
from fretbem.geometry.shapes import NurbsShape
from fretbem.scenes.builder import build
from fretbem.scenes.file import scene_from_data
from fretbem.simulation import LoadStep, Simulation, run
from fretbem.sliding import run_sliding, solve_sliding
from fretbem.sliding.track import Track
from fretbem.stress.closed_form import elliptical_pressure_stress, elliptical_shear_stress
from fretbem.stress.errors import StressInputError
from fretbem.stress.evaluate import stresses
from fretbem.verification.closed_forms import HertzLineContact

ROOT = Path(__file__).resolve().parents[2]
BASE = tomllib.loads((ROOT / "examples" / "gross_sliding_arc.toml").read_text())
E, NU, R, F = 73400.0, 0.33, 70.0, 0.3
#: the narrow pad's pressure against Hertz's: it bends under Q, so the twins are its
#: reference; 6.3 % at most measured (41 pairs at the start; 5.0 % at P = 160, 61 pairs)
NARROW = 0.07


def _hertz(load: float) -> HertzLineContact:
    return HertzLineContact.from_bodies(
        load=load, radius_upper=R, radius_lower=R,
        E_upper=E, nu_upper=NU, E_lower=E, nu_lower=NU,
    )  # fmt: skip


def study(basis="nurbs", pairs=41, load=100.0, pad=(6.5, 16.25), specimen=(12.0, 10.0),
          increments=6, frame="local"):  # fmt: skip
    """The sliding run along the arc (press, block to 3 a, to 6 a, back to 0) with the pair
    ``frame`` given and, with the shared frame, for each of its steps its fixed twin: the
    same bodies paired with the pad turned where that step's pairs were, pressed and driven
    into gross slip the same way (0.1 mm further: the shared frame does not see the pad's
    translation along its tangent, which moves the contact on an arc; local frames do,
    tests/framework/contact/test_pair_frames.py, so their twin is no longer the same)."""
    hertz = _hertz(load)
    simulation = _slid_there_and_back(
        BASE, basis, pairs, load, hertz.half_width, pad, specimen, increments
    )
    sliding = run_sliding(simulation, note=None, frame=frame)
    twins = twins_of(simulation, sliding, load) if frame == "shared" else None
    return simulation, sliding, twins, hertz


def _slid_there_and_back(scene, basis, pairs, load, a, pad, specimen, increments) -> Simulation:
    """``scene`` (a scene file's data) with the pad's and specimen's width and height, the
    family and pair count given, pressed by ``load``, slid 3 a and 6 a and back to 0."""
    data = copy.deepcopy(scene)
    data["pad"].update(width=pad[0], height=pad[1])
    data["specimen"].update(width=specimen[0], height=specimen[1])
    data["contact"].update(basis=basis, pairs=pairs)
    data["load"].update(
        steps=["press", "half", "slide", "back"],
        P=load,
        delta=[0.0, 3 * a, 6 * a, 0.0],
        increments=[1, increments, increments, 2 * increments],
    )
    return build(scene_from_data(data))[0]


def twins_of(simulation, sliding, load: float) -> list:
    """Each step's fixed twin: the same bodies paired with the pad turned where that step's
    pairs were, pressed and driven into gross slip the same way (0.1 mm further)."""
    twins = []
    for step, pair, offset, position in zip(
        sliding.steps, sliding.pairs, sliding.offsets, sliding.positions, strict=True
    ):
        sign = math.copysign(1.0, step.tangential) if abs(step.tangential) > 0.5 * F * load else 0
        placed = attrs.evolve(simulation.pair, turn=pair.turn, pivot=pair.pivot, frame=pair.frame)
        steps = (LoadStep("press", load, delta=0.0),)
        if sign:
            steps += (LoadStep("slide", load, delta=position - offset + 0.1 * sign, increments=2),)
        twins.append(run(Simulation(placed, steps, solver=simulation.solver, law=simulation.law)))
    return [t.steps[-1] for t in twins]


def measures(simulation, sliding, twins, hertz, shared=None) -> list[dict]:
    """Per step: where the face is along the arc, the pad's turn, the pressure and shear
    against the twin (if any), the shared frame's run (if given) and Hertz (arc coordinates
    from the pressure's centre), q = f p and Q against f P at the block and from the
    tractions (in the loads' frame), the latter's closed form: the pressure's centre e
    ahead of the pad's axis tilts the local normals there by phi = e / R, so Q / f P =
    (f - tan phi) / (f (1 + f tan phi)) (with Q's sign; exactly 1 in the shared frame)."""
    track = Track.of(simulation.pair)
    p0 = hertz.peak_pressure
    out = []
    twins = twins or [None] * len(sliding.steps)
    others = shared.steps if shared is not None else [None] * len(sliding.steps)
    for step, twin, other, pair, offset, position in zip(
        sliding.steps,
        twins,
        others,
        sliding.pairs,
        sliding.offsets,
        sliding.positions,
        strict=True,
    ):
        p, q = step.pressure, step.shear
        slip = np.asarray(step.increments[-1].slip)
        face = float(np.sum(p * slip) / np.sum(p))
        s = track.along(pair.pairing().points)
        centre = float(np.sum(s * p) / np.sum(p))
        touching = p > 0
        normal, tangential = step.resultant
        radial = pair.pairing().points[np.argmax(p)] - track.centre
        radial = radial / np.linalg.norm(radial)
        frame = pair.pairing().load_frame()[0]
        sign = math.copysign(1.0, step.tangential)
        tilt = math.tan(-track.rate * (centre - offset)) if pair.frame == "local" else 0.0
        extra = {} if twin is None else {
            "p_twin": np.max(np.abs(p - twin.pressure)) / p0,
            "q_twin": np.max(np.abs(q - twin.shear)) / p0,
        }  # fmt: skip
        if other is not None:
            extra["p_shared"] = np.max(np.abs(p - other.pressure)) / p0
        out.append({
            **extra,
            "offset": offset,
            "face": face,
            "block": position,
            "turn": pair.turn,
            "frame": abs(float(radial[0] * frame[1] - radial[1] * frame[0])),
            "p_hertz": np.max(np.abs(p - hertz.pressure(s - centre))) / p0,
            "coulomb": np.max(np.abs(np.abs(q[touching]) - F * p[touching])) / p0,
            "Q/fP": step.tangential / (F * step.normal),
            "tractions": tangential / (F * normal),
            "closed": (sign * F - tilt) / (F * (1.0 + sign * F * tilt)),
            "a/R": hertz.half_width / track.radius,
        })  # fmt: skip
    return out


def check(rows, *, hertz: float | None = None, margin: float = 0.002, block: float = 5e-4,
          turn: float = -1.0 / R):  # fmt: skip
    """The sliding run against its twins (to round-off), the pad turned by the face's
    slide over R and normal to the arc at the contact (within the bending shift's angle),
    Coulomb at every pair, Q from the tractions its closed form (f P in the shared frame)
    and at the block within ``block`` of it (the BEM block's equilibrium). Against Hertz:
    within ``hertz`` of p0 everywhere, or (None) on the track no farther than at the start
    plus ``margin``. ``turn``: the pad's turn per mm slid."""
    for row in rows:
        if "p_twin" in row:
            assert row["p_twin"] < 1e-9 and row["q_twin"] < 1e-9  # measured 5e-13
        assert abs(row["face"] - row["offset"]) < 1e-3  # measured 7e-5 mm
        assert (
            abs(row["turn"] - turn * row["offset"]) < 1e-11
        )  # round-off: 2e-12 measured (lagrange2)
        assert row["frame"] < 0.2 / R  # the centre 0.1 mm ahead of the axis (bending)
    for row in rows:
        assert row["p_hertz"] < (hertz if hertz is not None else rows[0]["p_hertz"] + margin)
    for row in rows[1:]:
        assert row["coulomb"] < 1e-12
        # measured 1e-6 (nurbs), 8.5e-5 (lagrange2 41 pairs): the closed form's centroid
        assert abs(row["tractions"] - row["closed"]) < 1.5e-4
        assert abs(row["Q/fP"] / row["tractions"] - 1.0) < block
    assert abs(rows[3]["block"]) < 1e-9
    assert rows[2]["offset"] > 0.9 * rows[2]["block"] > 0  # the face 6 a along, and back
    assert abs(rows[3]["offset"]) < 0.05 * rows[2]["offset"]


@pytest.fixture(scope="module")
def reference_arc():
    """The reference pad slid along the arc with the shared frame (and its twins) and with
    each pair's own frame (against the shared run)."""
    simulation, shared, twins, hertz = study(frame="shared")
    _, local, _, _ = study()
    return (shared, measures(simulation, shared, twins, hertz),
            measures(simulation, local, None, hertz, shared=shared))  # fmt: skip


def test_sliding_along_the_arc_is_the_pad_turned_where_it_slid(reference_arc):
    """In the shared frame, at every position the turned pad's tractions are those of the
    same bodies paired there without sliding (to 5e-13 p0); the pad turned by s / R;
    q = f p and Q = f P (0.99958 at the block: the BEM block's equilibrium, as on the flat).
    The narrow pad bends under Q (its contact 0.07 mm ahead of its axis), so its pressure
    is not Hertz's: within 3.2 % of it (6.3 % at the start, 41 pairs; measured)."""
    sliding, rows, _ = reference_arc
    check(rows, hertz=NARROW)
    assert sliding.repairings >= 4 * 6


def test_each_pairs_own_frame_changes_the_arc_by_the_order_of_a_over_r(reference_arc):
    """Each pair in the arc's own frame (the default): q = f p; the contact 0.064 mm ahead
    of the pad's axis tilts the local normals there by e / R, so Q / f P from the tractions
    is 0.99669 (its closed form (f - tan phi) / (f (1 + f tan phi)) to 1e-6) and 0.99627 at
    the block (the same 0.99958 of it as in the shared frame); the pressure differs from
    the shared frame's by 1.6 a/R of p0 at most (a/R = 0.0047; the pad bent ahead; 0.73 a/R
    on a wide pad, tests below; measured)."""
    rows = reference_arc[2]
    check(rows, hertz=NARROW)
    for row in rows:
        assert row["p_shared"] < 2.0 * row["a/R"]
    assert 0.99 < rows[2]["Q/fP"] < 0.9975  # 0.99636 measured


def test_larger_bodies_slide_with_the_hertz_pressure_of_both_radii():
    """A pad four times as wide on a specimen 40 x 20 mm: the pad hardly bends and the
    pressure along the arc is Hertz's with R* = 35 mm within 0.30 % of p0 (0.19 % at the
    start; measured, 31 pairs; 0.27 % at 61), the contact centred on the pad's axis,
    Q = f P."""
    simulation, sliding, twins, hertz = study(pairs=31, pad=(26.0, 16.25), specimen=(40.0, 20.0))
    rows = measures(simulation, sliding, twins, hertz)
    check(rows, hertz=0.004)
    for row in rows:
        assert row["frame"] < 1e-3 / R  # the pressure's peak within 1 um of the axis


@pytest.mark.slow
@pytest.mark.parametrize(
    ("basis", "pairs", "load"),
    [
        ("nurbs", 61, 100.0),
        ("nurbs", 97, 100.0),
        ("nurbs", 61, 60.0),
        ("nurbs", 61, 160.0),
        ("lagrange2", 41, 100.0),
        ("lagrange2", 61, 100.0),
        ("lagrange2", 61, 160.0),
    ],
)  # fmt: skip
def test_sliding_along_the_arc_at_several_loads_pair_counts_and_families(basis, pairs, load):
    simulation, sliding, twins, hertz = study(basis=basis, pairs=pairs, load=load)
    check(measures(simulation, sliding, twins, hertz), hertz=NARROW)


@pytest.mark.slow
@pytest.mark.parametrize(
    ("basis", "pairs", "hertz"),
    [("nurbs", 61, 0.004), ("nurbs", 97, 0.004), ("lagrange2", 61, None), ("lagrange2", 97, None)],
)
def test_larger_bodies_at_another_pair_count_and_family(basis, pairs, hertz):
    """nurbs 61 and 97: within 0.4 % of Hertz as at 31 (0.27 % measured at 61; at 41 the
    pairs fall so on the contact's edges that the largest error is 6.7 %, at the start
    without sliding too, so 41 is not among these). lagrange2 meets Hertz less closely on
    these curved faces without sliding too (3.2 % at 61 pairs, 1.9 % at 97 at the start);
    sliding stays within 0.3 % of its start (2.17 % at 97 pairs, measured)."""
    simulation, sliding, twins, hertz_form = study(
        basis=basis, pairs=pairs, pad=(26.0, 16.25), specimen=(40.0, 20.0)
    )
    check(measures(simulation, sliding, twins, hertz_form), hertz=hertz, margin=0.003)


#: the concave specimen's radius, the pad's (a cylinder inside the groove), the track's
#: half-width and the specimen's width and height (mm)
GROOVE, PAD, TRACK, WIDTH, HEIGHT = 70.0, 40.0, 5.0, 14.0, 10.0


def _groove() -> NurbsShape:
    """A specimen whose top is a concave arc of radius GROOVE about (0, GROOVE), lowest at
    the origin: its contact segment the track over |x| <= TRACK, clamped at its bottom."""
    down = -math.pi / 2
    edge, track = math.asin(WIDTH / 2 / GROOVE), math.asin(TRACK / GROOVE)

    def arc(start, end):
        return NurbsCurve.arc([0.0, GROOVE], GROOVE, start, end)

    right, contact, left = (
        arc(down + edge, down + track),
        arc(down + track, down - track),
        arc(down - track, down - edge),
    )
    return NurbsShape([
        Segment("bottom", NurbsCurve.line([-WIDTH / 2, -HEIGHT], [WIDTH / 2, -HEIGHT])),
        Segment("side_right", NurbsCurve.line([WIDTH / 2, -HEIGHT], right.points([0.0])[0])),
        Segment("flank_right", right),
        Segment("contact", contact),
        Segment("flank_left", left),
        Segment("side_left", NurbsCurve.line(left.points([1.0])[0], [-WIDTH / 2, -HEIGHT])),
    ])  # fmt: skip


def test_a_pad_slides_along_a_concave_arc_from_python():
    """A cylinder (R = 40 mm) in a concave groove (R = 70 mm) of the same material, drawn
    by hand (from Python: the scene file's cylinder specimen is convex), 1/R* = 1/40 - 1/70
    (a = 0.537 mm): the pad turns counterclockwise by s / R as it slides towards +x, its
    tractions those of the same bodies paired there (5e-13 p0), q = f p, Q = f P (0.99962
    at the block), the pressure within 2.6 % of Hertz's (0.73 % at the start; measured)."""
    load, pairs = 100.0, 41
    hertz = HertzLineContact.from_bodies(
        load=load, radius_upper=1.0 / (1.0 / PAD - 1.0 / GROOVE), radius_lower=math.inf,
        E_upper=E, nu_upper=NU, E_lower=E, nu_lower=NU,
    )  # fmt: skip
    a = hertz.half_width
    zone = 2.0 * a
    data = copy.deepcopy(BASE)
    data["pad"]["radius"] = PAD
    data["contact"].update(pairs=pairs, sliding=False, zone_width=zone)
    del data["contact"]["frame"]  # a sliding key: the scene here is read without sliding
    data["specimen"] = {  # its shape replaced below; the track twice as fine as the pad
        "shape": "flat", "length": 20.0, "thickness": 10.0,
        "elements": math.ceil(2 * (pairs - 2) * TRACK / zone),
    }  # fmt: skip
    data["load"].update(
        steps=["press", "half", "slide", "back"],
        delta=[0.0, 3 * a, 6 * a, 0.0],
        increments=[1, 6, 6, 12],
    )
    scene = scene_from_data(data)
    specimen = attrs.evolve(scene.specimen, shape=_groove(), support="clamped-bottom")
    simulation, _ = build(attrs.evolve(scene, specimen=specimen))
    sliding = run_sliding(simulation, note=None)
    track = Track.of(simulation.pair)
    assert np.allclose(track.centre, [0.0, GROOVE], atol=1e-9) and track.rate > 0
    rows = measures(simulation, sliding, None, hertz)
    check(rows, hertz=0.035, turn=1.0 / GROOVE)
    assert rows[2]["turn"] > 0.04  # 0.0457 rad after 3.2 mm


def test_the_specimens_stresses_follow_the_pad_and_the_pads_are_refused():
    """[stress] on a sliding run along the arc: the specimen's stresses (global frame) 0.5 a
    and a below the slid contact's centre, turned into the local frame, are McEwen's plus
    Smith-Liu's with q = f p in the normal and shear components (within 0.11 % and 0.28 %
    of p0 measured, 41 pairs) and in the hoop component as at the start (3.0 % there, the
    curved finite specimen's own; 3.8 % slid); the pad's, in its turned axes, are refused."""
    hertz = _hertz(100.0)
    a, p0 = hertz.half_width, hertz.peak_pressure
    data = copy.deepcopy(BASE)
    data["contact"]["pairs"] = 41
    data["load"].update(steps=["press", "slide"], delta=[0.0, 3 * a], increments=[1, 3])
    simulation, _ = build(scene_from_data(data))
    result = solve_sliding(simulation, say=lambda _: None)
    track = Track.of(simulation.pair)
    errors = {}
    for step, friction in zip(result.steps, (0.0, F), strict=True):
        p = step.pressure
        s = track.along(step.pair.pairing().points)
        turn = track.rate * float(np.sum(s * p) / np.sum(p))
        normal = np.array([[math.cos(turn), -math.sin(turn)], [math.sin(turn), math.cos(turn)]])
        normal = normal @ track.start
        tangent = np.array([normal[1], -normal[0]])
        for depth in (0.5 * a, a):
            point = track.centre + (R - depth) * normal
            sxx, syy, sxy, _ = stresses(result, step.name, point[None, :], body="lower")[0]
            tensor = np.array([[sxx, sxy], [sxy, syy]])
            local = [
                tangent @ tensor @ tangent,
                normal @ tensor @ normal,
                tangent @ tensor @ normal,
            ]
            exact = elliptical_pressure_stress(0.0, depth, a=a, p0=p0, centre=0.0, nu=NU)
            exact = exact + elliptical_shear_stress(
                0.0, depth, b=a, q0=friction * p0, centre=0.0, nu=NU
            )
            error = np.abs(np.array(local) - exact[:3]) / p0
            errors[step.name] = np.maximum(errors.get(step.name, 0.0), error)
    assert errors["slide"][1] < 0.002 and errors["slide"][2] < 0.004
    assert errors["slide"][0] < errors["press"][0] + 0.01
    with pytest.raises(StressInputError, match=r"turned axes.*\[stress\] body = 'lower'"):
        stresses(result, "slide", [[0.0, 1.0]], body="upper")


GROOVE_SCENE = tomllib.loads((ROOT / "examples" / "gross_sliding_groove.toml").read_text())


def groove_study(basis="nurbs", pairs=31, load=100.0, pad=(26.0, 16.25), specimen=(40.0, 20.0),
                 increments=6):  # fmt: skip
    """examples/gross_sliding_groove.toml (a cylinder pad R 40 in a groove R 70, from the
    scene file) pressed, slid 3 a and 6 a along the groove and back, with its measures
    against its fixed twins and Hertz with 1/R* = 1/R_pad - 1/R_groove."""
    hertz = HertzLineContact.from_bodies(
        load=load, radius_upper=1.0 / (1.0 / PAD - 1.0 / GROOVE), radius_lower=math.inf,
        E_upper=E, nu_upper=NU, E_lower=E, nu_lower=NU,
    )  # fmt: skip
    simulation = _slid_there_and_back(
        GROOVE_SCENE, basis, pairs, load, hertz.half_width, pad, specimen, increments
    )
    track = Track.of(simulation.pair)
    assert np.allclose(track.centre, [0.0, GROOVE], atol=1e-9)
    assert track.rate == pytest.approx(1.0 / GROOVE, rel=1e-12)
    sliding = run_sliding(simulation, note=None)
    return measures(simulation, sliding, None, hertz)


@pytest.mark.parametrize(("load", "hertz"), [(60.0, 0.008), (160.0, 0.011)])
def test_a_pad_slides_in_a_groove_from_the_scene_file(load, hertz):
    """A [specimen] shape = 'groove' (R 70 mm, 40 x 20 mm) under a cylinder pad (R 40 mm,
    26 mm wide), conforming contact, 31 pairs: the pad turns counterclockwise by s / R_groove
    as it slides towards +x, its tractions those of the same bodies paired there (3e-13 p0),
    q = f p, Q = f P (0.99998 at the block), the pressure along the groove within 0.65 % (P
    60) and 0.90 % (P 160) of Hertz's with 1/R* = 1/40 - 1/70 (0.20 / 0.22 % at the start;
    measured; 0.42 / 0.59 % with the shared frame, which is Hertz's own idealisation: all
    normals parallel, so each pair's own frame departs from it by the order of a/R)."""
    rows = groove_study(load=load)
    check(rows, hertz=hertz, turn=1.0 / GROOVE)
    assert rows[2]["turn"] > 0.02 and rows[2]["frame"] < 1e-3 / GROOVE


@pytest.mark.slow
@pytest.mark.parametrize(
    ("basis", "pairs", "load", "hertz"),
    [
        ("nurbs", 61, 60.0, 0.008),
        ("nurbs", 61, 100.0, 0.011),
        ("lagrange2", 61, 100.0, 0.035),
        ("lagrange2", 61, 160.0, 0.04),
        ("lagrange2", 97, 100.0, 0.035),
    ],
)  # fmt: skip
def test_a_pad_slides_in_a_groove_at_other_pair_counts_and_families(basis, pairs, load, hertz):
    """Measured against Hertz (1/R* = 1/R_pad - 1/R_groove), at the start / largest along
    the track: nurbs 61 pairs 0.16 / 0.71 % (P 60), 0.19 / 0.98 % (P 100; 0.47 / 0.70 % in
    the shared frame, Hertz's own idealisation); lagrange2, which
    meets Hertz less closely on curved faces without sliding too, 2.9 / 3.0 % (61, P 100),
    2.7 / 3.6 % (61, P 160), 2.1 / 3.0 % (97, P 100)."""
    check(groove_study(basis=basis, pairs=pairs, load=load), hertz=hertz, turn=1.0 / GROOVE)
