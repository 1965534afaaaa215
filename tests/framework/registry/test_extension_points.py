"""The extension points of issue 9: abstract Body, ContactPair, Solver, the law, the kernel,
the pair unknowns, named history loads, and the conformance checks of fretbem.testing."""

from __future__ import annotations

import inspect
import subprocess
import sys
from pathlib import Path

import attrs
import numpy as np
import pytest

from fretbem import Basis, Body, ContactPair, Simulation, Solver
from fretbem.basis import Refinement
from fretbem.bem.body import BemBody
from fretbem.bem.kernels import KelvinKernel
from fretbem.conditions import Displacement, LoadingBlock, Traction
from fretbem.contact.law import CoulombFriction, PairState
from fretbem.contact.pairs import NodeToNodePair
from fretbem.contact.unknowns import PairUnknowns, UnknownLayout, UnknownsLayoutError
from fretbem.geometry.boundary import Boundary, Segment
from fretbem.geometry.nurbs import NurbsCurve
from fretbem.material import Material
from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.simulation import LoadHistoryError, LoadStep, run
from fretbem.solvers.newton import SemiSmoothNewton, SolverSettingsError
from fretbem.testing.conformance import check_body, check_solver

STEEL = Material(210000.0, 0.3)


def block(conditions, name="block", elements=4):
    """A 2 x 1 block, tags bottom/right/top/left."""
    corners = np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]])
    tags = ("bottom", "right", "top", "left")
    boundary = Boundary(
        [Segment(t, NurbsCurve.line(corners[k], corners[(k + 1) % 4])) for k, t in enumerate(tags)]
    )
    return BemBody(
        boundary,
        STEEL,
        conditions,
        refinement={t: Refinement(elements) for t in tags},
        name=name,
    )


def test_abstract_classes_are_abstract_and_importable_from_the_top_level():
    for cls in (Basis, Body, ContactPair, Solver):
        assert inspect.isabstract(cls), cls
    assert not inspect.isabstract(BemBody) and not inspect.isabstract(SemiSmoothNewton)
    assert Simulation.__name__ == "Simulation"


def test_run_path_imports_no_study_plot_or_vtk_module():
    """Importing the top-level names and running imports no study, figure or VTK module;
    results must not import plot or vtk_ (writers depend on results, never the reverse)."""
    code = (
        "import sys\n"
        "from fretbem import Basis, Body, ContactPair, Solver, Simulation\n"
        "import fretbem.results, fretbem.simulation, fretbem.scenes\n"
        "bad = [m for m in sys.modules if m.startswith(('fretbem.studies',\n"
        "       'fretbem.output.figures',\n"
        "       'fretbem.output.vtk', 'fretbem.convergence')) or m in ('matplotlib', 'pyvista')]\n"
        "assert not bad, bad\n"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr


def test_bem_body_conformance():
    check_body(lambda: cattaneo_mindlin(pairs=21).pair.lower)  # clamped specimen
    check_body(lambda: cattaneo_mindlin(pairs=21).pair.upper)  # pad on a loading block


def test_loaded_body_conformance():
    check_body(
        lambda: block([Displacement("bottom"), Traction("right", x=1.0, load="bulk")]),
        tag="top",
    )


def test_semi_smooth_newton_conformance():
    check_solver(SemiSmoothNewton())


def test_check_body_names_a_broken_property():
    """A body whose response is not cached fails the check, naming the property."""

    @attrs.frozen(eq=False)
    class Uncached(BemBody):
        def contact_response(self, tag):
            return type(self).__mro__[1].contact_response(attrs.evolve(self), tag)

    def factory():
        lower = cattaneo_mindlin(pairs=21).pair.lower
        return Uncached(
            lower.boundary, lower.material, lower.conditions, lower.basis, lower.refinement
        )

    with pytest.raises(AssertionError, match="contact_response is cached"):
        check_body(factory)


def test_check_solver_names_a_broken_property():
    """A solver that ignores friction (returns q = 0) fails on the stick condition."""

    class Frictionless(SemiSmoothNewton):
        def solve_increment(self, problem, law, **kwargs):
            result = super().solve_increment(problem, CoulombFriction(1e-9), **kwargs)
            return result

    with pytest.raises(AssertionError, match=r"Frictionless.*does not hold"):
        check_solver(Frictionless())


@pytest.mark.parametrize(
    ("settings", "field"),
    [
        ({"tolerance": 0.0}, "tolerance"),
        ({"tolerance": 0.01}, "tolerance"),
        ({"max_iterations": 0}, "max_iterations"),
        ({"max_substeps": -1}, "max_substeps"),
    ],
)
def test_newton_settings_are_validated(settings, field):
    with pytest.raises(SolverSettingsError, match=rf"SemiSmoothNewton\.{field} must"):
        SemiSmoothNewton(**settings)


def test_pair_unknowns_round_trip():
    layout = UnknownLayout(3, ("upper",))
    x = np.arange(8.0)
    unknowns = PairUnknowns.from_vector(x, layout)
    np.testing.assert_array_equal(unknowns.pressure, [0, 1, 2])
    np.testing.assert_array_equal(unknowns.shear, [3, 4, 5])
    np.testing.assert_array_equal(unknowns.block("upper"), [6, 7])
    np.testing.assert_array_equal(unknowns.block("lower"), [0, 0])
    np.testing.assert_array_equal(unknowns.vector, x)
    assert unknowns.layout == layout
    with pytest.raises(UnknownsLayoutError, match="do not fit a layout of 3 pairs"):
        PairUnknowns.from_vector(np.zeros(7), layout)


def test_step_results_name_the_unknowns():
    result = run(cattaneo_mindlin(pairs=21, names=("A", "B"), tangential=(0.0, 10.0)))
    step = result["B"]
    named = step.pair_unknowns
    np.testing.assert_array_equal(named.pressure, step.pressure)
    np.testing.assert_array_equal(named.vector, step.unknowns)
    assert set(named.blocks) == {"upper"}
    assert set(np.unique(step.states)) <= set(PairState)
    assert result.describe()["solver"] == "SemiSmoothNewton"
    assert result.describe()["models"] == {"upper": "bem", "lower": "bem"}


def test_kelvin_kernel_plane_stress_is_plane_strain_with_reduced_nu():
    source, field, normal = np.array([0.1, -0.2]), np.array([[1.0, 0.5]]), np.array([[0.6, 0.8]])
    stress = KelvinKernel(80000.0, 0.3, plane_stress=True)
    strain = KelvinKernel(80000.0, 0.3 / 1.3)
    np.testing.assert_array_equal(
        stress.displacement(source, field), strain.displacement(source, field)
    )
    np.testing.assert_array_equal(
        stress.traction(source, field, normal), strain.traction(source, field, normal)
    )
    t, u = stress.traction_and_displacement(source, field, normal)
    np.testing.assert_allclose(t, stress.traction(source, field, normal), rtol=1e-13)
    np.testing.assert_allclose(u, stress.displacement(source, field), rtol=1e-13)
    assert KelvinKernel.of(Material(1.0, 0.25, plane_stress=True)).effective_nu == 0.2
    with pytest.raises(ValueError, match=r"Poisson.s ratio nu must lie in"):
        KelvinKernel(1.0, 0.5)


def test_load_scaled_traction_equals_the_fixed_traction():
    """A block with Traction(..., load="bulk") at amplitude 40 is the block with the fixed
    traction 40 (same coefficients to 1e-12), and the response's load column is linear."""
    fixed = block([Displacement("left"), Traction("right", x=40.0, y=-5.0)])
    scaled = block([Displacement("left"), Traction("right", x=8.0, y=-1.0, load="bulk")])
    assert scaled.load_names == ("bulk",) and fixed.load_names == ()
    expected = fixed.solve()
    got = scaled.solve({"bulk": 5.0})
    scale = np.abs(expected.displacement_coefficients).max()
    np.testing.assert_allclose(
        got.displacement_coefficients, expected.displacement_coefficients, atol=1e-12 * scale
    )
    np.testing.assert_allclose(
        got.traction_coefficients, expected.traction_coefficients, atol=1e-10 * 40.0
    )
    # contact response on the top face: base of the fixed body = load column x 5
    r_fixed, r_scaled = fixed.contact_response("top"), scaled.contact_response("top")
    np.testing.assert_allclose(
        r_scaled.base + 5.0 * r_scaled.load_map[..., 0], r_fixed.base, atol=1e-12 * scale
    )
    np.testing.assert_allclose(r_scaled.traction_map, r_fixed.traction_map, rtol=1e-12)


def test_history_drives_a_named_load():
    """A pad pressed on a flat specimen pulled by a bulk stress through the history: the
    step with loads {"bulk": s} equals the same scene with the fixed end traction s, and in
    the rig's order (P first, then the bulk stress) the bulk stress makes pairs slip."""

    def scene(conditions, steps=None):
        steps = steps or [LoadStep("A", 100.0, 0.0)]
        sim = cattaneo_mindlin(pairs=21, lower="flat")
        lower = attrs.evolve(sim.pair.lower, conditions=conditions)
        return attrs.evolve(sim, pair=type(sim.pair)(sim.pair.upper, lower), steps=steps)

    sigma = 3.0
    rollers = [Displacement("bottom", x=None, y=0.0), Displacement("end_left", y=None)]
    fixed = scene([*rollers, Traction("end_right", x=sigma, y=0.0)])
    bulk = [*rollers, Traction("end_right", x=1.0, y=0.0, load="bulk")]
    loaded = scene(bulk, [LoadStep("A", 100.0, 0.0, loads={"bulk": sigma})])
    a, b = run(fixed)["A"], run(loaded)["A"]
    p0 = np.max(a.pressure)
    np.testing.assert_allclose(b.pressure, a.pressure, atol=1e-9 * p0)
    np.testing.assert_allclose(b.shear, a.shear, atol=1e-9 * p0)
    assert b.loads == {"bulk": sigma}
    rig = run(
        scene(
            bulk,
            [
                LoadStep("A", 100.0, 0.0),
                LoadStep("B", 100.0, 0.0, loads={"bulk": 30.0}),
                LoadStep("C", 100.0, 0.0, loads={"bulk": -30.0}),
            ],
        )
    )
    assert rig["A"].count("slip") == 0 and rig["B"].count("slip") > 0  # measured 0 and 2
    assert np.abs(rig["B"].shear).max() > 5 * np.abs(rig["A"].shear).max()  # 18.1 vs 1.73
    for step in rig.steps:
        assert abs(step.resultant[0] - 100.0) < 1e-4 * 100.0  # measured 5.5e-5
    with pytest.raises(LoadHistoryError, match=r"drives loads \['wind'\]"):
        attrs.evolve(loaded, steps=[LoadStep("A", 100.0, 0.0, loads={"wind": 1.0})])


def test_loading_block_response_is_rigid_for_a_block_held_body():
    """The pad on its block, nothing else holding it: moving the block moves the face
    rigidly, and its block force balances the contact force (r_traction = -contact_force)."""
    response = cattaneo_mindlin(pairs=21).pair.upper.contact_response("contact")
    np.testing.assert_allclose(
        response.block_map, np.broadcast_to(np.eye(2), response.block_map.shape), atol=1e-9
    )
    scale = np.abs(response.contact_force).max()
    # equilibrium of the discretised pad, node by node: measured 3.9e-4 of the largest entry
    np.testing.assert_allclose(response.r_traction, -response.contact_force, atol=6e-4 * scale)
    _ = LoadingBlock  # the pad's condition


# -- the worked examples of the how-to pages (docs/how-to/extension_examples.py) -------------
sys.path.insert(0, str(Path(__file__).resolve().parents[3] / "docs" / "how-to"))
from extension_examples import FallbackSolver, TrescaFriction, WinklerFoundation  # noqa: E402


def winkler_simulation(law, steps, solver=None):
    """The reference pad (21 pairs) pressed on a Winkler bed with nodes under its face."""
    pad = cattaneo_mindlin(pairs=21).pair.upper
    x = np.sort(pad.contact_face("contact").points[:, 0])
    bed = WinklerFoundation(x, stiffness=1e6)
    return Simulation(
        NodeToNodePair(pad, bed), steps, solver or SemiSmoothNewton(), law=law, name="winkler"
    )


def test_winkler_foundation_is_a_body():
    check_body(lambda: WinklerFoundation(np.linspace(-1.0, 1.0, 9), stiffness=1e5))


def test_pad_on_a_winkler_bed():
    """The pad carries P and Q; the bed's own resultant (trapezoidal node weights) differs
    from the pad's (its shape-function integrals) by the quadrature only (measured 0.04 %)."""
    steps = [LoadStep("A", 100.0, 0.0), LoadStep("B", 100.0, 12.0)]
    result = run(winkler_simulation(CoulombFriction(0.3), steps))
    for step in result.steps:
        assert abs(step.resultant[0] - 100.0) < 1e-3 * 100.0  # measured 2e-5 (A), 3.9e-4 (B)
        assert abs(step.resultant[1] - step.tangential) < 1e-3 * 100.0  # measured 5.6e-5
    assert result["B"].count("slip") > 0 and result["B"].count("stick") > 0


def test_fallback_solver_conforms_and_rescues_a_failing_first_solver():
    check_solver(
        FallbackSolver(SemiSmoothNewton(max_iterations=1, max_substeps=0), SemiSmoothNewton())
    )


def test_tresca_law_bounds_the_shear_by_g():
    """Tresca friction: |q| <= g everywhere, |q| = g on slipping pairs, int q = Q."""
    g = 15.0
    steps = [LoadStep("A", 100.0, 0.0), LoadStep("B", 100.0, 5.0)]
    result = run(winkler_simulation(TrescaFriction(g), steps))
    step = result["B"]
    assert np.all(np.abs(step.shear) <= g * (1 + 1e-12))
    slipping = step.states == PairState.SLIP
    assert slipping.any()
    np.testing.assert_allclose(np.abs(step.shear[slipping]), g, rtol=1e-9)
    assert abs(step.resultant[1] - 5.0) < 1e-3 * 100.0  # measured 4.3e-4 (bed quadrature)
