"""H and G of both assembly paths (numpy, compiled) equal the round-1 assembler's.

The reference is a frozen copy of the assembler before the compiled kernels
(frozen_assembly_round1.py); the bodies are small but exercise every pair class: far,
mid, near (graded toward the closest point, at corners and across a narrow neck) and
singular, on curved and straight segments, graded and uniform, both families.
"""

import math
import sys

import frozen_assembly_round1 as frozen
import numpy as np
import pytest

from fretbem import registry as bases
from fretbem.basis import Refinement
from fretbem.bem import integration
from fretbem.geometry.nurbs import NurbsCurve

needs_numba = pytest.mark.skipif(
    not integration._numba_installed(), reason="the compiled path needs numba"
)
SHEAR_MODULUS, NU = 27594.0, 0.33


def _segments(family: str):
    """A pad-like body: a circular bottom arc, two sides, a top; graded toward corners."""
    radius, half, height = 12.0, 3.0, 5.0
    theta = math.asin(half / radius)
    bottom_y = radius - radius * math.cos(theta)
    curves = [
        NurbsCurve.arc((0.0, radius), radius, -math.pi / 2 - theta, -math.pi / 2 + theta),
        NurbsCurve.line((half, bottom_y), (half, height)),
        NurbsCurve.line((half, height), (-half, height)),
        NurbsCurve.line((-half, height), (-half, bottom_y)),
    ]
    refinements = [
        Refinement(elements=10),
        Refinement.graded(5, (0.0, 1.0), 8.0),
        Refinement.graded(4, (0.0, 1.0), 4.0),
        Refinement.graded(5, (0.0, 1.0), 8.0),
    ]
    family_class = bases.get(family)
    return [
        family_class.discretise(curve.reparametrised((0.0, 1.0)), refinement)
        for curve, refinement in zip(curves, refinements, strict=True)
    ]


def _assemble(segments, **settings):
    config = integration.IntegrationSettings(**settings)
    try:
        from fretbem.bem.kernels import KelvinKernel

        kernel = KelvinKernel(SHEAR_MODULUS, NU)
        return integration.Assembler(segments, kernel, config).assemble()
    except (ImportError, TypeError):
        return integration.Assembler(segments, SHEAR_MODULUS, NU, config).assemble()


@pytest.fixture(scope="module", params=["nurbs", "lagrange2"])
def case(request):
    segments = _segments(request.param)
    reference = frozen.Assembler(segments, SHEAR_MODULUS, NU).assemble()
    return segments, reference


@pytest.mark.parametrize("compiled", [False, pytest.param(True, marks=needs_numba)])
def test_matrices_equal_round_one(case, compiled):
    segments, (h_ref, g_ref) = case
    h, g = _assemble(segments, compiled=compiled)
    # measured: 4e-16 relative (summation order only)
    assert np.max(np.abs(h - h_ref)) <= 1e-12 * np.max(np.abs(h_ref))
    assert np.max(np.abs(g - g_ref)) <= 1e-12 * np.max(np.abs(g_ref))


def test_every_pair_class_is_exercised(case):
    """The body must reach near and mid pairs, or the comparison above proves little."""
    segments, _ = case
    colloc = frozen.Collocation.of(segments)
    settings = frozen.IntegrationSettings()
    counts = np.zeros(3, int)
    for basis in segments:
        samples = np.linspace(-1.0, 1.0, 9)
        n_el = basis.n_elements
        x, *_ = basis.geometry(np.repeat(np.arange(n_el), 9), np.tile(samples, n_el))
        _, _, jw, _ = frozen._element_rule(
            basis, frozen.QuadratureRule.gauss_legendre(settings.mid_points)
        )
        dist = np.linalg.norm(colloc.points[:, None, None] - x.reshape(n_el, 9, 2)[None], axis=-1)
        ratio = dist.min(axis=2) / jw.sum(axis=1)
        counts += [
            np.sum(ratio >= settings.far_ratio),
            np.sum((ratio >= settings.near_ratio) & (ratio < settings.far_ratio)),
            np.sum(ratio < settings.near_ratio),
        ]
    assert np.all(counts > 20), counts


@needs_numba
def test_rigid_translation_in_null_space(case):
    """H annihilates rigid translations (the rigid-body identity), compiled path too."""
    segments, _ = case
    h, _ = _assemble(segments, compiled=True)
    n = h.shape[0] // 2
    for j in range(2):
        unit = np.zeros((n, 2))
        unit[:, j] = 1.0
        assert np.max(np.abs(h @ unit.ravel())) <= 1e-12 * np.max(np.abs(h))


def test_compiled_true_without_numba_is_a_clear_error(monkeypatch):
    monkeypatch.setattr(integration, "_numba_installed", lambda: False)
    with pytest.raises(integration.CompiledKernelsUnavailableError, match="pip install numba"):
        _assemble(_segments("lagrange2"), compiled=True)


def test_automatic_choice_by_size(monkeypatch):
    """Small bodies stay on numpy (no numba import) unless the kernels are loaded already."""
    segments = _segments("lagrange2")
    try:
        from fretbem.bem.kernels import KelvinKernel

        assembler = integration.Assembler(segments, KelvinKernel(SHEAR_MODULUS, NU))
    except (ImportError, TypeError):
        assembler = integration.Assembler(segments, SHEAR_MODULUS, NU)
    monkeypatch.delitem(sys.modules, "fretbem.bem.compiled_loops", raising=False)
    monkeypatch.setattr(integration.LOOP_CHOICE, "spent", 0)
    assert assembler.point_element_pairs < integration.COMPILED_MIN_PAIRS
    assert not assembler.uses_compiled
    monkeypatch.setattr(integration, "COMPILED_MIN_PAIRS", assembler.point_element_pairs)
    assert assembler.uses_compiled == integration._numba_installed()


def test_numpy_loops_until_their_cost_matches_loading_numba(monkeypatch):
    """Ski rental: repeated small assemblies switch to compiled once numpy spent the budget."""
    monkeypatch.delitem(sys.modules, "fretbem.bem.compiled_loops", raising=False)
    monkeypatch.setattr(integration, "_numba_installed", lambda: True)
    monkeypatch.setattr(integration.LOOP_CHOICE, "spent", 0)
    from fretbem.bem.kernels import KelvinKernel

    assembler = integration.Assembler(
        _segments("lagrange2"), KelvinKernel(SHEAR_MODULUS, NU), integration.IntegrationSettings()
    )
    work = assembler.point_element_pairs
    monkeypatch.setattr(integration, "COMPILED_MIN_PAIRS", 3 * work)
    choices = []
    for _ in range(4):
        choices.append(assembler.uses_compiled)
        if not choices[-1]:
            monkeypatch.setattr(
                integration.LOOP_CHOICE, "spent", integration.LOOP_CHOICE.spent + work
            )
    assert choices == [False, False, True, True]
    monkeypatch.setattr(integration.LOOP_CHOICE, "spent", 0)  # the numpy path counts its work
    monkeypatch.setattr(integration, "COMPILED_MIN_PAIRS", 10 * work)
    assembler.assemble()
    assert integration.LOOP_CHOICE.spent == work
