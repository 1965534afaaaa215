"""A body symmetric about the y axis is solved as two half systems (even and odd unknowns):
the same unknowns as the full solve to round-off, for both families, at several sizes, on
the path that keeps A for a point image and on the one that never builds A; a body, a
matrix or conditions that are not symmetric are solved whole."""

from __future__ import annotations

import attrs
import numpy as np
import pytest

from fretbem.accuracy.adaptive import remesh
from fretbem.bem import image_factor, mirror_split, system
from fretbem.bem.layout import BLOCK, CONTACT, DISPLACEMENT, TRACTION
from fretbem.scenes import cattaneo_mindlin
from fretbem.simulation import run
from fretbem.testing.caches import forget_assembled

MIRROR_SPLIT = system._mirror_split


@pytest.fixture(autouse=True)
def _every_size(monkeypatch):
    """Split bodies of any size (the run splits only those of MIN_ROWS rows or more)."""
    monkeypatch.setattr(mirror_split, "MIN_ROWS", 0)


def _split_counted(monkeypatch, split: bool) -> list:
    """Count the systems factorised as two halves (none when ``split`` is False)."""
    used = []

    class Counted(mirror_split.SplitFactor):
        def __init__(self, *args):
            used.append(True)
            super().__init__(*args)

    monkeypatch.setattr(mirror_split, "SplitFactor", Counted)
    if not split:
        monkeypatch.setattr(system, "_mirror_split", lambda body, kinds: None)
    return used


def _synthetic(functions: int, seed: int):
    """Mirror-symmetric H and G (M = X + P X P^T) of a boundary whose function b mirrors to
    functions - 1 - b (the middle one its own mirror when odd), with symmetric kinds."""
    rng = np.random.default_rng(seed)
    q = functions - 1 - np.arange(functions)
    n = 2 * functions
    mirror = (2 * q[:, None] + np.arange(2)).ravel()
    sign = np.tile([-1.0, 1.0], functions)
    p = np.zeros((n, n))
    p[mirror, np.arange(n)] = sign
    h, g = (x + p @ x @ p.T for x in (rng.normal(size=(n, n)) + 4 * np.eye(n) for _ in "hg"))
    half = rng.choice([TRACTION, DISPLACEMENT, CONTACT], size=(functions, 2))
    kinds = np.maximum(half, half[q]).ravel()  # symmetric: a dof's mirror of its kind
    points = np.column_stack([np.linspace(-1, 1, functions), np.ones(functions)])
    representative = (points[:, 0] * points[:, 1] > (points[q, 0] * points[q, 1])) | (
        q == np.arange(functions)
    )
    return h, g, kinds, mirror_split.MirrorSplit.of(q, representative)


@pytest.mark.parametrize(("functions", "seed"), [(7, 0), (8, 1), (31, 2), (300, 3)])
def test_the_halves_solve_the_full_system(functions, seed):
    h, g, kinds, split = _synthetic(functions, seed)
    assert split.symmetric_kinds(kinds)
    solves_u = (kinds == TRACTION) | (kinds == CONTACT)
    contact = np.flatnonzero(kinds == CONTACT)
    matrix = np.where(solves_u, h, -g)
    halves = mirror_split.build(split, h, g, solves_u, contact)
    assert halves is not None
    assert [len(m) for m in halves.matrices] == [functions, functions]  # half of 2 N each
    factor = mirror_split.SplitFactor(split, halves)
    rhs = np.random.default_rng(seed).normal(size=(len(kinds), 3))
    full = np.linalg.solve(matrix, rhs)
    # measured at most 2.4e-13 of the largest unknown (300 functions)
    assert np.abs(factor.solve(np.asfortranarray(rhs)) - full).max() <= 1e-12 * np.abs(full).max()
    out = np.empty((len(kinds), len(contact)))
    factor.solve_contact(contact, out)
    full = np.linalg.solve(matrix, g[:, contact])
    assert np.abs(out - full).max() <= 1e-12 * np.abs(full).max()
    assert not factor.failed
    # into F-ordered columns (the run's response) straight, not through the buffer: the same
    halves = mirror_split.build(split, h, g, solves_u, contact)
    columns = np.empty((len(kinds), len(contact)), order="F")
    mirror_split.SplitFactor(split, halves).solve_contact(contact, columns)
    assert np.array_equal(columns, out)


def test_an_asymmetric_matrix_or_kinds_is_no_split():
    h, g, kinds, split = _synthetic(31, 4)
    solves_u = (kinds == TRACTION) | (kinds == CONTACT)
    contact = np.flatnonzero(kinds == CONTACT)
    for matrix in (h, g):
        tampered = matrix.copy()
        tampered[5, 40] += 1e-9 * np.abs(matrix).max()
        pair = (tampered, g) if matrix is h else (h, tampered)
        assert mirror_split.build(split, *pair, solves_u, contact) is None
    other = kinds.copy()
    other[0] = BLOCK
    assert not split.symmetric_kinds(other)


def _systems(monkeypatch, split: bool, keep_rows: int, **overrides):
    """Both bodies' factorised systems of a cold reference scene, and which were split."""
    forget_assembled()
    used = _split_counted(monkeypatch, split)
    monkeypatch.setattr(image_factor, "KEEP_MAX_ROWS", keep_rows)
    pair = cattaneo_mindlin(models={}, **overrides).pair
    out = [pair.upper.system((pair.upper_tag,)), pair.lower.system((pair.lower_tag,))]
    return out, used


@pytest.mark.parametrize(
    ("basis", "pairs", "lower"),
    [("nurbs", 21, "arc"), ("nurbs", 61, "flat"), ("lagrange2", 31, "arc"),
     ("lagrange2", 41, "flat")],
)  # fmt: skip
@pytest.mark.parametrize("keep_rows", [2048, 0])  # A kept for an image / never built
def test_split_systems_equal_the_full_solve(basis, pairs, lower, keep_rows, monkeypatch):
    overrides = {"basis": basis, "pairs": pairs, "lower": lower}
    full, used = _systems(monkeypatch, False, keep_rows, **overrides)
    assert not used
    monkeypatch.undo()
    monkeypatch.setattr(mirror_split, "MIN_ROWS", 0)
    split, used = _systems(monkeypatch, True, keep_rows, **overrides)
    # both bodies split (a specimen solved as the pad's image needs no factors of its own)
    assert len(used) == (1 if lower == "arc" and keep_rows else 2)
    for a, b in zip(full, split, strict=True):
        for name in ("base", "contact_response", "load_response"):
            x, y = getattr(a, name), getattr(b, name)
            if not x.size:
                continue
            # measured at most 2.7e-12 of the largest entry (of the contact columns)
            assert np.abs(x - y).max() <= 2e-11 * max(np.abs(x).max(), 1e-300), name
        for column in range(a.block_response.shape[1]):
            # the block's unit translation moves the body rigidly (u = 1, t = 0): both solves
            # miss it by round-off amplified in the block's traction unknowns (the full
            # solve 1.1e-8 and 1.7e-8 at 21 pairs, the halves 3.1e-9 and 1.6e-9)
            rigid = np.where(a.solves_u, np.arange(len(a.kinds)) % 2 == column, 0.0)
            full_error = np.abs(a.block_response[:, column] - rigid).max()
            split_error = np.abs(b.block_response[:, column] - rigid).max()
            assert split_error <= max(2 * full_error, 1e-12)


@pytest.mark.parametrize(("basis", "iterations"), [("nurbs", [8, 5, 5, 4, 5]),
                                                    ("lagrange2", [7, 5, 5, 4, 5])])  # fmt: skip
def test_the_reference_cycle_is_unchanged(basis, iterations, monkeypatch):
    results = []
    for split in (False, True):
        forget_assembled()
        with monkeypatch.context() as patch:
            used = _split_counted(patch, split)
            results.append(run(cattaneo_mindlin(models={}, basis=basis)))
        assert bool(used) == split
    own, halves = results
    scale = max(np.abs(step.pressure).max() for step in own.steps)
    for a, b in zip(own.steps, halves.steps, strict=True):
        assert a.iterations == b.iterations
        # measured 9.3e-13 (nurbs), 1.3e-12 (lagrange2)
        assert np.abs(a.unknowns - b.unknowns).max() <= 1e-11 * scale
    assert [step.iterations for step in halves.steps] == iterations


def test_an_asymmetric_body_is_solved_whole(monkeypatch):
    simulation = cattaneo_mindlin(models={}, pairs=21)
    body = remesh(simulation, np.array([0.1]), 21, ratio=4.0).pair.upper  # a kink off centre
    body = attrs.evolve(body)
    kinds = body.layout(("contact",)).kinds.ravel()
    assert MIRROR_SPLIT(body, kinds) is None


def test_a_matrix_that_breaks_the_symmetry_is_solved_whole(monkeypatch):
    """The assembled H tampered in one entry: the split declines and the full solve runs."""
    forget_assembled()
    pair = cattaneo_mindlin(models={}, pairs=21).pair
    body, tag = pair.upper, pair.upper_tag
    h, _ = body.system_matrices(system.g_free_segments(body, body.layout((tag,))))
    h[3, 17] += 1e-8 * np.abs(h).max()
    built = []
    build = mirror_split.build
    monkeypatch.setattr(mirror_split, "build", lambda *a: built.append(out := build(*a)) or out)
    solved = body.system((tag,))
    assert built == [None]
    assert np.all(np.isfinite(solved.contact_response))


@pytest.mark.parametrize(
    "index",
    [np.arange(12), np.arange(12)[::-1], np.array([5, 4, 3, 0, 1, 2, 9, 7]), np.array([3]),
     np.array([], dtype=int), np.random.default_rng(0).permutation(40),
     (2 * np.r_[np.arange(10)[::-1], np.arange(10, 30)[::-1], 30][:, None] + [0, 1]).ravel()],
)  # fmt: skip
def test_an_index_gathers_and_scatters_as_fancy_indexing(index):
    ix = mirror_split.Index(index)
    source = np.random.default_rng(1).normal(size=(3, 70))
    for axis, array in ((1, source), (0, source.T.copy())):
        out = np.empty((3, len(index)) if axis else (len(index), 3))
        ix.take(array, axis, out)
        expected = array[:, index] if axis else array[index]
        assert np.array_equal(out, expected)
        scattered, reference = np.zeros(array.shape), np.zeros(array.shape)
        ix.put(scattered, out, axis)
        if axis:
            reference[:, index] = out
        else:
            reference[index] = out
        assert np.array_equal(scattered, reference)


def test_a_small_body_is_solved_whole(monkeypatch):
    """Below MIN_ROWS the halves cost what they save: the 61-pair pad is solved whole."""
    monkeypatch.setattr(mirror_split, "MIN_ROWS", 800)
    forget_assembled()
    pair = cattaneo_mindlin(models={}, pairs=61).pair
    body = pair.upper
    kinds = body.layout((pair.upper_tag,)).kinds.ravel()
    assert len(kinds) < 800
    assert MIRROR_SPLIT(body, kinds) is None
    monkeypatch.setattr(mirror_split, "MIN_ROWS", 0)
    assert MIRROR_SPLIT(body, kinds) is not None


@pytest.mark.parametrize(("functions", "seed"), [(9, 0), (40, 1), (151, 2)])
def test_the_compiled_build_gives_the_numpy_halves_and_check(functions, seed, monkeypatch):
    """Once numba is loaded the halves are built in one compiled pass: the numpy loop's
    half matrices and contact right-hand sides bit for bit, and the same refusal of a
    matrix that breaks the symmetry."""
    pytest.importorskip("numba")
    from fretbem.bem import compiled_loops  # noqa: F401 - loads numba as the assembly does

    h, g, kinds, split = _synthetic(functions, seed)
    solves_u, contact = kinds != DISPLACEMENT, np.flatnonzero(kinds == CONTACT)
    assert contact.size
    built = {}
    for compiled in (True, False):
        with monkeypatch.context() as patch:
            if not compiled:
                patch.setattr(mirror_split, "_COMPILED", "no such module")
            built[compiled] = mirror_split.build(split, h, g, solves_u, contact)
            broken = h.copy()
            broken[3, 5] += 1e-9 * np.abs(h).max()
            assert mirror_split.build(split, broken, g, solves_u, contact) is None
    for ours, theirs in zip(
        built[True].matrices + built[True].contact,
        built[False].matrices + built[False].contact,
        strict=True,
    ):
        assert np.array_equal(ours, theirs)
