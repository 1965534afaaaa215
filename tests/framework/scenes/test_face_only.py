"""Half-plane bodies between library shapes are built from their faces alone.

The half-plane model reads only the contact face (``HalfPlaneModel.face_only``): between
library shapes the scene builder hands it the face (an ``OpenFace``) and builds no closed
boundary; the shapes' own dimension checks still refuse bad input with the same messages,
and a drawn ('nurbs') shape's boundary is still built and checked.
"""

from __future__ import annotations

import math

import attrs
import numpy as np
import pytest

from fretbem.geometry import boundary as boundary_module
from fretbem.geometry.boundary import BoundaryError, OpenFace
from fretbem.geometry.shapes import (
    CylinderPad,
    CylinderSpecimen,
    FlatSpecimen,
    GrooveSpecimen,
    NurbsShape,
    ShapeError,
)
from fretbem.halfplane.scene import half_plane_model
from fretbem.scenes import builder
from fretbem.scenes.builder import build
from fretbem.scenes.file import scene_from_data


def _scene(pad=None, specimen=None, contact=None):
    data = {
        "pad": {"shape": "cylinder", "model": "half-plane", **(pad or {})},
        "specimen": {"shape": "cylinder", "model": "half-plane", **(specimen or {})},
        "contact": {"pairs": 21, **(contact or {})},
        "load": {"P": 100.0, "Q": [0.0, 18.0]},
    }
    return scene_from_data(data)


@pytest.fixture
def boundaries(monkeypatch):
    """The tags of every closed Boundary built (the builder's shape cache emptied first)."""
    built: list[tuple[str, ...]] = []
    check = boundary_module.Boundary.__attrs_post_init__

    def counted(self):
        built.append(self.tags)
        check(self)

    monkeypatch.setattr(boundary_module.Boundary, "__attrs_post_init__", counted)
    builder._built.cache_clear()
    yield built
    builder._built.cache_clear()


@pytest.mark.parametrize("specimen", ["cylinder", "flat", "groove"])
def test_half_planes_build_no_closed_boundary(boundaries, specimen):
    """Two half-planes on library shapes: no Boundary built, each body given an OpenFace."""
    shapes = {"cylinder": {}, "flat": {"shape": "flat"}, "groove": {"shape": "groove",
                                                                  "radius": 140.0}}  # fmt: skip
    contact = {"pairing": "node-to-segment"} if specimen == "groove" else {}
    simulation, _ = build(_scene(specimen=shapes[specimen], contact=contact))
    assert boundaries == []
    assert simulation.pair.lower.contact_face("contact").n_nodes == 21


def test_a_bem_specimen_under_a_half_plane_pad_builds_its_own_boundary_only(boundaries):
    """The BEM specimen's boundary is built and checked; the half-plane pad's is not."""
    build(_scene(specimen={"model": "bem"}))
    assert boundaries == [("bottom", "side_right", "flank_right", "contact", "flank_left",
                           "side_left")]  # fmt: skip


def test_the_face_is_the_boundary_s_face():
    """A half-plane body built from the OpenFace has the nodes of one built from the closed
    boundary, bit for bit (the same face segments)."""
    scene = _scene()
    simulation, _ = build(scene)
    zone = builder.zone_half_width(scene)
    pad_face = builder._pad_face(scene, zone, True)
    boundary = scene.specimen.shape.boundary(pad_face, zone)
    family = builder._family(scene, "specimen")
    levels = builder.refinements(scene, family, zone, pad=False)
    whole = half_plane_model("lower", scene=scene, boundary=boundary,
                             material=scene.specimen.material, conditions=[], family=family,
                             refinement=levels)  # fmt: skip
    nodes = simulation.pair.lower.contact_face("contact").points
    assert np.array_equal(nodes, whole.contact_face("contact").points)


def test_the_shapes_checks_still_refuse_bad_dimensions():
    """A zone wider than the specimen, a cylinder specimen of another radius: the messages
    the closed boundary's build gave."""
    with pytest.raises(ShapeError, match="must lie inside the specimen face"):
        build(_scene(pad={"width": 30.0}, specimen={"width": 0.5}, contact={"zone": 1.5}))
    with pytest.raises(ShapeError, match="faces node to node only a cylinder pad"):
        build(_scene(specimen={"radius": 35.0, "width": 5.0}))


def test_a_drawn_shape_is_checked_as_a_boundary(boundaries):
    """A 'nurbs' pad (here the library pad's own segments) is built and checked as a closed
    boundary, and so is the library specimen facing it; a drawn boundary that crosses itself
    is refused for a half-plane body too."""
    zone = builder.zone_half_width(_scene())
    scene = _scene(contact={"zone_width": zone})
    drawn = NurbsShape(scene.pad.shape.boundary(zone).segments)
    boundaries.clear()
    build(attrs.evolve(scene, pad=attrs.evolve(scene.pad, shape=drawn)))
    assert len(boundaries) == 2
    segments = list(drawn.segments)
    top = segments[4]
    crossing = boundary_module.Segment(top.tag, top.curve.reversed())
    bad = NurbsShape([*segments[:4], crossing, segments[5]])
    with pytest.raises(BoundaryError):
        build(attrs.evolve(scene, pad=attrs.evolve(scene.pad, shape=bad)))


def test_the_open_face_has_the_face_tags():
    """OpenFace keeps the face's segments and tags in order."""
    face = CylinderPad(70.0, 10.0, 10.0).face(0.5)
    assert OpenFace(face).tags == ("flank_left", "contact", "flank_right")


@pytest.mark.parametrize("seed", range(4))
def test_a_face_the_shapes_accept_closes_into_a_valid_boundary(seed):
    """The face path skips the closed boundary's checks for library shapes: over random
    dimensions (near their limits too), whenever the pad's and the specimen's faces are
    accepted, both closed boundaries build and pass every check."""
    rng = np.random.default_rng(seed)
    accepted = 0
    for _ in range(40):
        radius = rng.uniform(5.0, 100.0)
        width = rng.uniform(0.05, 1.999) * radius
        sag = radius - math.sqrt(radius**2 - (width / 2) ** 2)
        try:
            pad = CylinderPad(radius, width, sag * rng.uniform(1.0001, 3.0) + 1e-6)
            zone = rng.uniform(0.001, 1.2) * width / 2
            pad_face = pad.face(zone)
        except ShapeError:
            continue
        kind = rng.integers(3)
        spec_width = rng.uniform(0.5, 1.999) * (radius if kind else 2 * width)
        try:
            if kind == 0:
                specimen = FlatSpecimen(spec_width, rng.uniform(0.01, 10.0))
            elif kind == 1:
                s_sag = radius - math.sqrt(max(radius**2 - (spec_width / 2) ** 2, 0.0))
                specimen = CylinderSpecimen(radius, spec_width, s_sag * 1.01 + 1e-6)
            else:
                big = radius * rng.uniform(1.01, 3.0)
                specimen = GrooveSpecimen(big, min(spec_width, 1.99 * big), rng.uniform(0.1, 5))
            specimen.face(pad_face, zone)
        except ShapeError:
            continue
        pad.boundary(zone)
        specimen.boundary(pad_face, zone)
        accepted += 1
    assert accepted >= 10
