"""Per-face discretisation keys ([pad], [specimen] over [contact]) and [contact] pairing."""

import pytest

from fretbem.contact.node_to_segment import NodeToSegmentPair
from fretbem.contact.pairs import NodeToNodePair
from fretbem.scenes.builder import build, faces_differ
from fretbem.scenes.file import SceneFileError, load_scene, scene_from_data


def _scene(pad=None, specimen=None, contact=None, **tables):
    data = {
        "pad": {"shape": "cylinder", **(pad or {})},
        "specimen": {"shape": "cylinder", **(specimen or {})},
        "contact": {"pairs": 21, **(contact or {})},
        "load": {"P": 100.0, "Q": [0.0, 18.0]},
    }
    data.update(tables)
    return scene_from_data(data)


def test_defaults_keep_node_to_node():
    """Without per-face keys the faces are alike and paired node to node."""
    simulation, _ = build(_scene())
    assert type(simulation.pair) is NodeToNodePair
    assert faces_differ(_scene()) == []


def test_face_keys_override_the_contact_defaults():
    """[pad] basis and pairs, [specimen] elements: each body's face as asked."""
    scene = _scene(
        pad={"basis": "lagrange2", "pairs": 31},
        specimen={"elements": 12, "degree": 3},
        contact={"pairing": "node-to-segment"},
    )
    simulation, _ = build(scene)
    pair = simulation.pair
    assert isinstance(pair, NodeToSegmentPair)
    assert pair.upper.family.name == "lagrange2"
    assert pair.upper.contact_face("contact").n_nodes == 31
    refinement = pair.lower.face_refinement("contact")
    assert (refinement.elements, refinement.degree) == (12, 3)
    assert pair.lower.contact_face("contact").n_nodes == 15  # 12 elements, degree 3
    assert pair.n_pairs == 15  # the coarser face carries the pairs


def test_node_to_node_with_differing_faces_names_the_keys():
    """Faces that differ under node-to-node pairing: the keys and the fix."""
    scene = _scene(pad={"pairs": 31})
    with pytest.raises(SceneFileError, match=r"pairs 31 vs 21.*pairing = 'node-to-segment'"):
        build(scene)


@pytest.mark.parametrize(
    ("tables", "message"),
    [
        ({"pad": {"pairs": 21, "elements": 4}}, r"\[pad\] gives both pairs and elements"),
        ({"specimen": {"basis": "cubic"}}, r"\[specimen\] basis: unknown basis family 'cubic'"),
        ({"pad": {"pairs": 0}}, r"\[pad\] pairs must be >= 1"),
        ({"contact": {"pairing": "mortar"}}, r"\[contact\] pairing: unknown contact pairing"),
        (
            {"contact": {"mesh": "adaptive"}, "pad": {"pairs": 31}},
            r"\[pad\] pairs does not apply to mesh = 'adaptive'",
        ),
        ({"pad": {"pairs": "many"}}, r"\[pad\] pairs must be an integer"),
    ],
)
def test_bad_face_keys(tables, message):
    """Each bad per-face key is one message naming it."""
    data = {
        "pad": {"shape": "cylinder"},
        "specimen": {"shape": "cylinder"},
        "load": {"P": 100.0, "Q": [0.0, 18.0]},
    }
    for name, table in tables.items():
        data.setdefault(name, {}).update(table)
    with pytest.raises(SceneFileError, match=message):
        scene_from_data(data)


def test_a_count_the_family_cannot_reach_names_the_face_key():
    """lagrange2 puts 2 k + 1 points on a face: 30 is refused naming [pad] pairs."""
    scene = _scene(pad={"basis": "lagrange2", "pairs": 30}, contact={"pairing": "node-to-segment"})
    with pytest.raises(SceneFileError, match=r"\[pad\] pairs: the lagrange2 family cannot"):
        build(scene)


def test_run_wide_pairs_set_every_face():
    """build(scene, pairs=n) (the companion level, --pairs) puts every face at n points, at
    most n for a family that cannot reach it."""
    scene = _scene(pad={"basis": "lagrange2", "pairs": 41}, contact={"pairing": "node-to-segment"})
    simulation, _ = build(scene, pairs=16)
    assert simulation.pair.lower.contact_face("contact").n_nodes == 16
    assert simulation.pair.upper.contact_face("contact").n_nodes == 15


def test_half_plane_specimen_under_a_finer_pad():
    """A half-plane specimen (lagrange2, 21) under a BEM pad (nurbs, 41): it solves and
    balances P and Q."""
    from fretbem.simulation import run

    scene = _scene(
        pad={"pairs": 41},
        specimen={"model": "half-plane", "basis": "lagrange2"},
        contact={"pairing": "node-to-segment"},
    )
    result = run(build(scene)[0])
    assert result.simulation.pair.n_pairs == 21
    for step in result.steps:
        assert abs(step.resultant[0] - step.normal) < 1e-3 * step.normal
        assert abs(step.resultant[1] - step.tangential) < 1e-3 * step.normal


def test_the_example_reads():
    """examples/mismatched_faces.toml: a 97-point lagrange2 pad on a 61-point nurbs specimen."""
    from pathlib import Path

    path = Path(__file__).parents[3] / "examples" / "mismatched_faces.toml"
    scene = load_scene(path)
    assert (scene.pad.basis, scene.pad.pairs, scene.contact.pairing) == (
        "lagrange2",
        97,
        "node-to-segment",
    )
    assert faces_differ(scene) == ["basis", "pairs"]


def test_the_command_runs_the_example(tmp_path, capsys):
    """fretbem run on the example: both faces in the summary line, checks passed, an
    estimate from the companion level (every face at about half the pairs)."""
    import json
    from pathlib import Path

    from fretbem.app import cli

    path = Path(__file__).parents[3] / "examples" / "mismatched_faces.toml"
    out = tmp_path / "out"
    code = cli.main(["run", str(path), "--out", str(out), "--no-figures", "--no-vtk"])
    assert code == 0
    text = capsys.readouterr().out
    assert "pad face lagrange2 (degree 2, 97 nodes), specimen face nurbs (degree 2, 61 nodes)" in (
        text
    )
    summary = json.loads((out / "summary.json").read_text())
    assert summary["scene"]["faces"]["upper"]["nodes"] == 97
    assert summary["scene"]["pairing"] == "NodeToSegmentPair"
