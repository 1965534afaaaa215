"""A body whose every segment is the exact point image of the last assembled body's takes
that body's H and G permuted (:mod:`fretbem.bem.image_matrices`): G bit for bit what its own
assembly gives, H to round-off in the rigid-body terms, the reference cycle's unknowns
unchanged. Any body that is not such an image (another material, shape, mesh, a half-plane
body) is assembled: each test would fail if the permuted matrices were taken for it."""

from __future__ import annotations

import attrs
import numpy as np
import pytest

from fretbem.basis import Refinement
from fretbem.bem import image_factor, image_matrices, mirror_split, system
from fretbem.bem import layout as bem_layout
from fretbem.bem.body import BemBody
from fretbem.bem.integration import IntegrationSettings
from fretbem.bem.system import g_free_segments
from fretbem.scenes import cattaneo_mindlin
from fretbem.simulation import run
from fretbem.testing.caches import forget_assembled

DERIVED = image_matrices.derived


def _assembled(body: BemBody, g_free=(), monkeypatch=None) -> tuple[np.ndarray, np.ndarray]:
    """The body's own assembly (a fresh copy of it, nothing permuted)."""
    with monkeypatch.context() as patch:
        patch.setattr(image_matrices, "permutation", lambda *args: None)
        return attrs.evolve(body)._assembled(tuple(g_free))


def _pad_then_specimen(changed=None, **overrides):
    """The scene's pad assembled as a run assembles it, then the specimen's system matrices
    (``changed``: replaces the specimen); the specimen, its H and G and its g_free."""
    forget_assembled()
    pair = cattaneo_mindlin(models={}, **overrides).pair
    pad = pair.upper
    specimen = changed(pair.lower) if changed else pair.lower
    pad.system_matrices(g_free_segments(pad, pad.layout((pair.upper_tag,))))
    free = g_free_segments(specimen, specimen.layout((pair.lower_tag,)))
    return specimen, specimen.system_matrices(free), free


def _read_columns(body: BemBody, g_free) -> np.ndarray:
    """G's columns a solve reads: those of the segments outside ``g_free``."""
    read = np.ones(2 * body.n_functions, bool)
    for k in g_free:
        read[2 * body.function_slice(k).start : 2 * body.function_slice(k).stop] = False
    return read


def _rigid_body_entries(body: BemBody) -> np.ndarray:
    """Where H holds rigid-body terms: each row against the functions of its own element
    (the entries a row sum in another segment order moves)."""
    colloc = body.collocation
    mask = np.zeros((2 * body.n_functions,) * 2, bool)
    for k, basis in enumerate(body.segments):
        rows = np.flatnonzero(colloc.segment == k)
        functions = body.offsets[k] + basis.connectivity[colloc.element[rows]]
        for i in range(2):
            for j in range(2):
                mask[(2 * rows[:, None] + i), 2 * functions + j] = True
    return mask


@pytest.mark.parametrize("basis", ["nurbs", "lagrange2"])
@pytest.mark.parametrize("pairs", [21, 61, 241, 481])
def test_the_image_specimen_takes_the_pads_matrices_permuted(basis, pairs, monkeypatch):
    specimen, (h, g), free = _pad_then_specimen(basis=basis, pairs=pairs)
    assert image_matrices.source_of(h) is not None  # permuted, not assembled
    own_h, own_g = _assembled(specimen, free, monkeypatch)
    read = _read_columns(specimen, free)  # the others 0 where the numpy loops left them out
    # G has no rigid-body terms: bit for bit with the same loops; measured 1.3e-16 of its
    # largest entry where the pad took the numpy loops and the own assembly the compiled
    worst_g = np.abs(g[:, read] - own_g[:, read]).max() / np.abs(own_g).max()
    assert worst_g <= 3e-16
    terms = _rigid_body_entries(specimen)
    # off the rigid-body terms H is the pad's as G is: bit for bit with the same loops,
    # 7.4e-17 of its largest entry at 481 pairs where the loops differed
    scale = np.abs(own_h).max()
    assert np.abs(h[~terms] - own_h[~terms]).max() <= 3e-16 * scale
    # the rigid-body terms, row sums in the pad's segment order: measured 8.9e-16 (21 pairs)
    # to 2.9e-15 (481) of H's largest entry
    assert np.abs(h - own_h).max() <= 4e-15 * scale


@pytest.mark.parametrize("basis", ["nurbs", "lagrange2"])
@pytest.mark.parametrize("pairs", [21, 61])
def test_the_reference_cycle_is_unchanged(basis, pairs, monkeypatch):
    """The specimen's unknowns come from the pad's factors and solved columns either way
    (:mod:`fretbem.bem.image_factor`): measured bit for bit, 21 to 481 pairs."""
    forget_assembled()
    permuted = run(cattaneo_mindlin(models={}, basis=basis, pairs=pairs))
    forget_assembled()
    monkeypatch.setattr(image_matrices, "permutation", lambda *args: None)
    assembled = run(cattaneo_mindlin(models={}, basis=basis, pairs=pairs))
    for a, b in zip(permuted.steps, assembled.steps, strict=True):
        assert a.iterations == b.iterations
        assert np.array_equal(a.unknowns, b.unknowns)


def _material(body):
    return attrs.evolve(body, material=attrs.evolve(body.material, E=2.0 * body.material.E))


def _remeshed(body):
    return body.with_face_refinement("contact", Refinement(elements=7))


def _settings(body):
    return attrs.evolve(body, integration=IntegrationSettings(far_points=8))


@pytest.mark.parametrize(
    ("overrides", "changed"),
    [({"lower": "flat"}, None), ({"E_lower": 2e5}, None), ({"nu_lower": 0.3}, None),
     ({}, _material), ({}, _remeshed), ({}, _settings), ({"radius": 70.0}, None)],
    ids=["flat", "E", "nu", "material", "mesh", "settings", "control"],
)  # fmt: skip
@pytest.mark.parametrize("basis", ["nurbs", "lagrange2"])
def test_a_specimen_that_is_no_image_is_assembled(basis, overrides, changed, monkeypatch):
    specimen, (h, g), free = _pad_then_specimen(changed, basis=basis, pairs=21, **overrides)
    permuted = image_matrices.source_of(h) is not None
    own_h, own_g = _assembled(specimen, free, monkeypatch)
    if overrides == {"radius": 70.0}:  # the control: the reference specimen is an image
        assert permuted
        assert not np.array_equal(h, own_h)  # the rigid-body terms in the pad's order
        return
    assert not permuted
    assert np.array_equal(h, own_h) and np.array_equal(g, own_g)


@pytest.mark.parametrize("models", [{"lower": "half-plane"}, {"upper": "half-plane"}])
def test_a_half_plane_body_takes_no_permuted_matrices(models, monkeypatch):
    forget_assembled()
    calls = []
    monkeypatch.setattr(
        image_matrices, "derived", lambda *args: calls.append(out := DERIVED(*args)) or out
    )
    result = run(cattaneo_mindlin(models=models, pairs=21))
    assert calls and not any(out is not None for out in calls)
    assert result.steps[-1].iterations > 0


def test_g_left_out_on_the_pad_is_never_lent_where_the_specimen_reads_it(monkeypatch):
    """The pad's G without its traction-free columns (the numpy loops) serves a specimen
    that leaves out the same columns, and not one that reads them all."""
    forget_assembled()
    pair = cattaneo_mindlin(models={}, pairs=21).pair
    numpy = IntegrationSettings(compiled=False)
    pad, specimen = (attrs.evolve(b, integration=numpy) for b in (pair.upper, pair.lower))
    pad_free = g_free_segments(pad, pad.layout((pair.upper_tag,)))
    pad.system_matrices(pad_free)
    h, g = specimen.matrices()  # every column
    assert image_matrices.source_of(h) is None
    own_h, own_g = _assembled(specimen, (), monkeypatch)
    assert np.array_equal(g, own_g) and np.array_equal(h, own_h)
    # and the other way: the pad whole, the specimen's system matrices taken from it
    forget_assembled()
    pad, specimen = (attrs.evolve(b, integration=numpy) for b in (pair.upper, pair.lower))
    pad.matrices()
    free = g_free_segments(specimen, specimen.layout((pair.lower_tag,)))
    h, g = specimen.system_matrices(free)
    assert image_matrices.source_of(h) is not None
    read = _read_columns(specimen, free)
    own_h, own_g = _assembled(specimen, free, monkeypatch)
    assert np.array_equal(g[:, read], own_g[:, read])


def test_differing_kinds_build_the_matrix(monkeypatch):
    """A body with permuted H and G whose unknowns' kinds differ from the kept factor's in
    one column is not solved with it (its A is not the kept one permuted)."""
    forget_assembled()
    pair = cattaneo_mindlin(models={}, pairs=21).pair
    pair.upper.system((pair.upper_tag,))
    specimen = pair.lower
    layout = specimen.layout((pair.lower_tag,))
    h, g = specimen.system_matrices(g_free_segments(specimen, layout))
    source = image_matrices.source_of(h)
    assert source is not None
    kinds = layout.kinds.ravel()
    solves_u = (kinds == bem_layout.TRACTION) | (kinds == bem_layout.CONTACT)
    parameters = system.collocation_parameters(
        h, g, kinds, layout.known.ravel(), layout.loads.reshape(len(layout.loads), kinds.size),
        np.flatnonzero(kinds == bem_layout.BLOCK), np.flatnonzero(kinds == bem_layout.CONTACT),
    )  # fmt: skip
    counts = np.bincount(specimen.collocation.segment, minlength=len(specimen.segments))
    first_rows = 2 * np.concatenate([[0], np.cumsum(counts)])
    kept = image_factor._KEPT[0]

    def solve(kinds_u):
        image_factor._KEPT[0] = kept
        return image_factor.solve_as_image(
            specimen.segments, 2 * specimen.offsets, first_rows, image_matrices.image_of,
            None, parameters.copy(order="F"), solves_u=kinds_u, permuted_from=source.h,
        )  # fmt: skip

    flipped = solves_u.copy()
    flipped[5] = not flipped[5]
    assert solve(flipped) is None
    assert solve(solves_u) is not None  # the same kinds: served
    # a kept factor built from another H: only a block check could tell, and A is not built
    assert image_factor.solve_as_image(
        specimen.segments, 2 * specimen.offsets, first_rows, image_matrices.image_of,
        None, parameters.copy(order="F"), solves_u=solves_u, permuted_from=h,
    ) is None  # fmt: skip


def test_runs_merge_where_both_sides_continue():
    s = slice
    pairs = [(s(0, 4), s(10, 14)), (s(4, 6), s(14, 16)), (s(6, 9), s(0, 3)), (s(9, 10), s(3, 4))]
    assert image_matrices._runs(pairs) == [(s(0, 6), s(10, 16)), (s(6, 10), s(0, 4))]
    assert image_matrices._runs(pairs[:1]) == pairs[:1]


@pytest.mark.parametrize("permuted", [True, False])
def test_a_pad_the_halves_solve_keeps_no_matrix(permuted, monkeypatch):
    """A pad solved as two halves builds no A: a specimen with H and G permuted from it takes
    its factors (the kinds checked); one assembled on its own is factorised itself, as
    nothing can compare its matrix; both give the same specimen system to round-off."""
    monkeypatch.setattr(mirror_split, "MIN_ROWS", 0)
    if not permuted:
        monkeypatch.setattr(image_matrices, "permutation", lambda *args: None)
    forget_assembled()
    pair = cattaneo_mindlin(models={}, pairs=21).pair
    pad = pair.upper.system((pair.upper_tag,))
    assert image_factor._KEPT[0].matrix is None
    specimen = pair.lower.system((pair.lower_tag,))
    assert (specimen.image_of is pad) is permuted
    if permuted:
        return
    forget_assembled()
    monkeypatch.undo()
    monkeypatch.setattr(mirror_split, "MIN_ROWS", 0)
    pair = cattaneo_mindlin(models={}, pairs=21).pair
    pair.upper.system((pair.upper_tag,))
    shared = pair.lower.system((pair.lower_tag,))
    assert shared.image_of is not None
    scale = np.abs(shared.contact_response).max()
    # measured 1.2e-13 of the largest entry (the halves' and the full LU's round-off)
    assert np.abs(shared.contact_response - specimen.contact_response).max() <= 5e-13 * scale


@pytest.mark.parametrize("basis", ["nurbs", "lagrange2"])
def test_the_image_specimen_shares_the_pads_contact_maps_read_only(basis):
    forget_assembled()
    pair = cattaneo_mindlin(models={}, basis=basis, pairs=21).pair
    pad = pair.upper.contact_response(pair.upper_tag)
    specimen = pair.lower.contact_response(pair.lower_tag)
    for name in ("traction_map", "contact_force"):
        assert getattr(specimen, name) is getattr(pad, name)
        assert not getattr(pad, name).flags.writeable
    e_matrix = system.face_values_matrix(pair.lower, pair.lower_tag)
    assert e_matrix is system.face_values_matrix(pair.lower, pair.lower_tag)  # kept
    assert not e_matrix.flags.writeable
    assert np.array_equal(e_matrix, system._face_values_matrix(pair.lower, pair.lower_tag))


def test_the_pads_matrices_are_let_go_once_they_served():
    """Kept from the pad's assembly until the specimen's system took the pad's factors (the
    pad has released its own by then): not through the cycle's steps."""
    forget_assembled()
    pair = cattaneo_mindlin(models={}, pairs=21).pair
    pair.upper.system((pair.upper_tag,))
    assert image_matrices._KEPT[0] is not None
    system_ = pair.lower.system((pair.lower_tag,))
    assert system_.image_of is not None
    assert image_matrices._KEPT[0] is None


def _specimen_system(basis, pairs, formed: bool):
    """The specimen's system after the pad's, its H and G formed (permuted) first or never
    formed (:func:`fretbem.bem.system._permuted_parameters`)."""
    forget_assembled()
    pair = cattaneo_mindlin(models={}, basis=basis, pairs=pairs).pair
    pair.upper.system((pair.upper_tag,))
    specimen = pair.lower
    if formed:
        h, _ = specimen.system_matrices(
            g_free_segments(specimen, specimen.layout((pair.lower_tag,)))
        )
        assert image_matrices.source_of(h) is not None
    return specimen, specimen.system((pair.lower_tag,))


@pytest.mark.parametrize("basis", ["nurbs", "lagrange2"])
@pytest.mark.parametrize("pairs", [21, 61, 241])
def test_the_image_specimens_system_without_its_matrices_is_the_same(basis, pairs, monkeypatch):
    """Its H and G are never formed (nothing permuted, nothing assembled), its system is the
    one solved with them permuted bit for bit, and the kept H and G are let go."""
    derived = []
    monkeypatch.setattr(
        image_matrices, "derived", lambda *args: derived.append(out := DERIVED(*args)) or out
    )
    _, formed = _specimen_system(basis, pairs, formed=True)
    assert any(out is not None for out in derived)
    derived.clear()
    specimen, never = _specimen_system(basis, pairs, formed=False)
    assert all(out is None for out in derived) and never.image_of is not None
    assert image_matrices._KEPT[0] is None and image_factor._KEPT[0] is None
    assert not any(isinstance(key, tuple) and "matrices" in key[0] for key in specimen._cache)
    assert "matrices" not in specimen._cache and "assembly" not in specimen.timings
    for name in ("base", "block_response", "contact_response", "load_response"):
        assert np.array_equal(getattr(formed, name), getattr(never, name)), name


def test_a_specimen_held_displaced_solves_its_own_general_columns():
    """A specimen whose bottom is displaced: its z0 column differs from the pad's and is
    solved with the pad's factors, the same numbers as with its H and G formed."""
    from fretbem.conditions import Displacement

    systems = []
    for formed in (True, False):
        forget_assembled()
        pair = cattaneo_mindlin(models={}, pairs=21).pair
        pair.upper.system((pair.upper_tag,))
        specimen = attrs.evolve(pair.lower, conditions=(Displacement("bottom", 0.0, -1e-3),))
        if formed:
            specimen.system_matrices(g_free_segments(specimen, specimen.layout((pair.lower_tag,))))
        systems.append(specimen.system((pair.lower_tag,)))
    formed, never = systems
    assert never.image_of is not None and np.abs(never.base).max() > 0
    for name in ("base", "block_response", "contact_response", "load_response"):
        assert np.array_equal(getattr(formed, name), getattr(never, name)), name


def test_a_specimen_whose_contact_dofs_do_not_correspond_forms_its_matrices(monkeypatch):
    """Where the kept factorisation cannot serve without the matrices (here refused
    outright), H and G are formed and the system solved as before, the same numbers."""
    monkeypatch.setattr(image_factor, "solve_permuted", lambda *args, **kwargs: None)
    _, never = _specimen_system("nurbs", 21, formed=False)
    _, formed = _specimen_system("nurbs", 21, formed=True)
    assert never.image_of is not None  # served by the formed path's comparison instead
    for name in ("base", "contact_response", "load_response"):
        assert np.array_equal(getattr(formed, name), getattr(never, name)), name


@pytest.mark.parametrize("basis", ["nurbs", "lagrange2"])
def test_a_split_pad_keeps_its_contact_columns_unformed_and_they_serve_alike(basis, monkeypatch):
    """A pad the mirror split's halves solve keeps only its general parameter columns for
    its point image (the halves build their own contact right-hand sides); formed on
    request they are the pad's parameter columns bit for bit, and the specimen's system is
    the same whether served from its permuted solution or through its formed matrices'
    comparison (which forms them)."""
    monkeypatch.setattr(mirror_split, "MIN_ROWS", 100)  # the 61-pair pad splits
    systems = {}
    for formed in (False, True):
        forget_assembled()
        pair = cattaneo_mindlin(models={}, basis=basis, pairs=61).pair
        pad = pair.upper
        pad_h, pad_g = pad.system_matrices(g_free_segments(pad, pad.layout((pair.upper_tag,))))
        pad.system((pair.upper_tag,))
        kept = image_factor._KEPT[0]
        assert isinstance(kept.parameters, image_factor.LazyParameters)
        kinds = pad.system((pair.upper_tag,)).kinds
        layout = pad.layout((pair.upper_tag,))
        expected = system.collocation_parameters(
            pad_h, pad_g, kinds, layout.known.ravel(),
            layout.loads.reshape(len(layout.loads), kinds.size),
            np.flatnonzero(kinds == bem_layout.BLOCK), np.flatnonzero(kinds == bem_layout.CONTACT),
        )  # fmt: skip
        full = kept.parameters.full()
        assert full.shape == kept.parameters.shape and full.flags.f_contiguous
        assert np.array_equal(full, expected)
        specimen = pair.lower
        if formed:  # the comparison path: H and G permuted, the kept columns formed
            monkeypatch.setattr(image_factor, "solve_permuted", lambda *a, **k: None)
        systems[formed] = specimen.system((pair.lower_tag,))
        assert systems[formed].image_of is not None
        monkeypatch.undo()
        monkeypatch.setattr(mirror_split, "MIN_ROWS", 100)
    for name in ("base", "block_response", "contact_response", "load_response"):
        assert np.array_equal(getattr(systems[False], name), getattr(systems[True], name)), name
