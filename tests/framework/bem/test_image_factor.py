"""A specimen that is the pad's point image, with corresponding boundary conditions, is solved
with the pad's factorisation: its unknowns equal its own factorisation's to round-off, and a
body that is no image (or whose matrix differs) is factorised as before."""

from __future__ import annotations

import attrs
import numpy as np
import pytest

from fretbem.bem import assembly, image_factor, image_matrices, system
from fretbem.scenes import cattaneo_mindlin
from fretbem.simulation import run
from fretbem.testing.caches import forget_assembled

SOLVE_AS_IMAGE = image_factor.solve_as_image
SOLVE_PERMUTED = image_factor.solve_permuted


def _run(shared: bool, monkeypatch, **overrides):
    """A cold reference run; the number of systems solved with a kept factorisation (with
    H and G permuted, or never formed: :func:`~fretbem.bem.image_factor.solve_permuted`)."""
    forget_assembled()
    calls = []

    def counted(solve):
        def solved(*args, **kwargs):
            out = solve(*args, **kwargs) if shared else None
            calls.append(out is not None)
            return out

        return solved

    monkeypatch.setattr(image_factor, "solve_as_image", counted(SOLVE_AS_IMAGE))
    monkeypatch.setattr(image_factor, "solve_permuted", counted(SOLVE_PERMUTED))
    return run(cattaneo_mindlin(models={}, **overrides)), sum(calls)


@pytest.mark.parametrize("basis", ["nurbs", "lagrange2"])
@pytest.mark.parametrize("pairs", [21, 61])
def test_the_image_specimen_takes_the_pads_factors_to_round_off(basis, pairs, monkeypatch):
    own, _ = _run(False, monkeypatch, basis=basis, pairs=pairs)
    shared, count = _run(True, monkeypatch, basis=basis, pairs=pairs)
    assert count == 1
    scale = max(np.abs(step.pressure).max() for step in own.steps)
    for a, b in zip(own.steps, shared.steps, strict=True):
        assert a.iterations == b.iterations
        # measured 4.5e-13 (61 pairs), 1.3e-13 (21)
        assert np.abs(a.unknowns - b.unknowns).max() <= 5e-12 * scale


def test_a_flat_specimen_is_no_image_of_the_pad(monkeypatch):
    _, count = _run(True, monkeypatch, pairs=21, lower="flat")
    assert count == 0


def test_a_differing_matrix_is_factorised_again(monkeypatch):
    """A kept factorisation whose matrix differs from the specimen's (permuted) in one entry
    off the diagonal blocks, or beyond round-off on them, serves no body."""
    forget_assembled()
    systems = []
    build = system.collocation_system

    def kept_copies(*args):
        matrix, parameters = build(*args)
        systems.append((matrix.copy(order="F"), parameters.copy(order="F")))
        return matrix, parameters

    monkeypatch.setattr(system, "collocation_system", kept_copies)
    # the specimen assembled and its matrix built, not permuted from the pad's
    monkeypatch.setattr(image_matrices, "permutation", lambda *args: None)
    pair = cattaneo_mindlin(models={}, pairs=21).pair
    body = pair.lower
    pair.upper.system((pair.upper_tag,))
    body.system((pair.lower_tag,))
    matrix, parameters = systems[1]
    counts = np.bincount(body.collocation.segment, minlength=len(body.segments))
    first_rows = 2 * np.concatenate([[0], np.cumsum(counts)])
    first_dofs = 2 * body.offsets

    def solve(kept):
        image_factor._KEPT[0] = kept
        return image_factor.solve_as_image(
            body.segments, first_dofs, first_rows, assembly.BLOCKS.image,
            matrix, parameters.copy(order="F"),
        )  # fmt: skip

    forget_assembled()
    pair.upper.release_matrices()
    pair.upper._cache.clear()
    pair.upper.system((pair.upper_tag,))
    kept = image_factor._KEPT[0]
    assert solve(kept) is not None  # the untouched factorisation serves
    for row, column in ((0, len(matrix) - 1), (0, 0)):  # off the diagonal blocks, on them
        tampered = kept.matrix.copy(order="F")
        tampered[row, column] += 1e-9 * (1 + abs(tampered[row, column]))
        assert solve(attrs.evolve(kept, matrix=tampered)) is None


@pytest.mark.parametrize("basis", ["nurbs", "lagrange2"])
def test_the_image_specimen_takes_the_pads_contact_maps_bit_for_bit(basis, monkeypatch):
    """Its traction map and contact force are the pad's (E, the face weights and the contact
    rows of the contact columns equal): the same numbers as computing them."""
    responses, used = [], []
    image_response = system._image_response
    for share in (False, True):
        forget_assembled()

        def shared(*args, share=share):
            out = image_response(*args) if share else None
            used.append(out is not None)
            return out

        monkeypatch.setattr(system, "_image_response", shared)
        pair = cattaneo_mindlin(models={}, basis=basis, pairs=21).pair
        pair.upper.contact_response(pair.upper_tag)
        responses.append(pair.lower.contact_response(pair.lower_tag))
    assert used == [False, False, False, True]  # the pad (a block) and the specimen, twice
    own, taken = responses
    assert not taken.has_block and taken.rotation is None
    for name in ("base", "traction_map", "block_map", "load_map", "r_base", "r_traction",
                 "r_block", "r_load", "contact_force"):  # fmt: skip
        assert np.array_equal(getattr(own, name), getattr(taken, name)), name


def _differenced_columns(parameters, kept, rows):
    """The columns' comparison as every column differenced (the check before the exact
    comparison came first)."""
    worst = np.zeros(parameters.shape[1])
    for own, other in rows:
        np.maximum(worst, np.abs(parameters[own] - kept[other]).max(axis=0), out=worst)
    return worst <= image_factor.ROUNDING * np.abs(kept).max(axis=0)


def test_parameter_columns_are_told_same_as_when_every_column_is_differenced():
    rng = np.random.default_rng(3)
    kept = np.asfortranarray(rng.standard_normal((12, 7)))
    rows = [(slice(0, 5), slice(7, 12)), (slice(5, 12), slice(0, 7))]
    parameters = np.empty_like(kept, order="F")
    for own, other in rows:
        parameters[own] = kept[other]
    scale = np.abs(kept).max(axis=0)
    parameters[1, 1] += 0.25 * image_factor.ROUNDING * scale[1]  # within round-off: same
    parameters[8, 3] += 4.0 * image_factor.ROUNDING * scale[3]  # beyond: solved again
    parameters[2, 5] = np.nan  # never the same
    same = image_factor._same_columns(parameters, kept, rows)
    assert same.tolist() == [True, True, True, False, True, False, True]
    assert np.array_equal(same, _differenced_columns(parameters, kept, rows))
    parameters[8, 3], parameters[2, 5] = kept[3, 3], kept[9, 5]
    assert image_factor._same_columns(parameters, kept, rows).all()


@pytest.mark.parametrize("axis", [0, 1])
@pytest.mark.parametrize("rows", [[2, 3, 4, 5], [5, 2, 3], [1, 3, 4], [4], []])
def test_the_image_check_reads_the_face_rows_it_would_gather(rows, axis):
    """Rows (the image check) and columns (the contact parameter columns) alike."""
    matrix = np.asfortranarray(np.arange(48.0).reshape(8, 6))
    matrix = matrix if axis == 0 else np.asfortranarray(matrix.T)
    rows = np.array(rows, dtype=int)
    taken = system._taken(matrix, rows, axis)
    assert np.array_equal(taken, matrix.take(rows, axis=axis))
    assert np.shares_memory(taken, matrix) == (rows.size > 0 and bool(np.all(np.diff(rows) == 1)))


def test_blocks_are_told_close_as_when_every_entry_is_differenced():
    kept = np.random.default_rng(5).standard_normal((6, 4))
    tolerance = image_factor.ROUNDING * np.abs(kept).max()
    for change, close in ((0.0, True), (0.5 * tolerance, True), (2.0 * tolerance, False),
                          (np.nan, False)):  # fmt: skip
        block = kept.copy()
        block[2, 3] += change
        whole = bool(np.all(np.abs(block - kept) <= tolerance))
        assert image_factor._close(block, kept) is close is whole


@pytest.mark.parametrize("basis", ["nurbs", "lagrange2"])
@pytest.mark.parametrize("pairs", [21, 61])
def test_a_specimen_served_by_permutation_shares_the_pads_contact_block(basis, pairs):
    """The specimen whose system took the pad's solution permuted (H and G never formed)
    has the pad's contact rows of the contact columns, bit for bit, by construction: the
    contact response skips comparing them (``shares_contact_block``), and they are equal."""
    forget_assembled()
    pair = cattaneo_mindlin(models={}, basis=basis, pairs=pairs).pair
    pair.upper.contact_response(pair.upper_tag)
    taken = pair.lower.contact_response(pair.lower_tag)
    assert taken.traction_map is pair.upper.contact_response(pair.upper_tag).traction_map
    specimen = pair.lower.system((pair.lower_tag,))
    pad = pair.upper.system((pair.upper_tag,))
    assert specimen.shares_contact_block and specimen.image_of is pad
    assert not pad.shares_contact_block
    assert specimen._contact_response is None  # its contact columns not formed for a run
    own = specimen.contact_response[specimen.contact_dofs]
    other = pad.contact_response[pad.contact_dofs]
    assert np.array_equal(own, other)
