"""Conformance checks for body models and solvers (re-exported by :mod:`fretbem.testing`).

Only the public abstract APIs are used (:class:`~fretbem.body.Body`,
:class:`~fretbem.solvers.newton.Solver`), so the checks hold for any implementation. A failure
raises ``AssertionError`` naming the implementation and the property that does not hold.
"""

from __future__ import annotations

from collections.abc import Callable

import attrs
import numpy as np

from fretbem.body import Body, ContactFace, ContactResponse
from fretbem.contact.law import ContactState, PairState
from fretbem.material import Material
from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.solvers.newton import IncrementResult, Solver

#: relative tolerance of the solver checks (on p and q against f p0, on forces against P)
SOLVER_TOL = 1e-8


def _require(ok: bool, who: str, prop: str, detail: str = "") -> None:
    if not ok:
        raise AssertionError(f"{who}: {prop} does not hold" + (f" ({detail})" if detail else ""))


def _shape(array, shape, who, name) -> None:
    got = np.shape(array)
    _require(got == shape, who, f"{name} has shape {shape}", f"got {got}")
    _require(bool(np.all(np.isfinite(array))), who, f"{name} is finite")


def _check_face(face: ContactFace, who: str) -> int:
    _require(isinstance(face, ContactFace), who, "contact_face returns a ContactFace")
    n = len(face.points)
    _require(n >= 2, who, "the contact face has at least two nodes", f"got {n}")
    _shape(face.points, (n, 2), who, "ContactFace.points")
    _shape(face.normals, (n, 2), who, "ContactFace.normals")
    lengths = np.linalg.norm(face.normals, axis=1)
    _require(np.allclose(lengths, 1.0, atol=1e-12), who, "face normals are unit vectors")
    return n


def _check_response(response: ContactResponse, n: int, k: int, who: str) -> None:
    _require(isinstance(response, ContactResponse), who, "contact_response is a ContactResponse")
    for name, shape in (
        ("base", (n, 2)),
        ("traction_map", (n, 2, 2 * n)),
        ("block_map", (n, 2, 2)),
        ("load_map", (n, 2, k)),
        ("r_base", (2,)),
        ("r_traction", (2, 2 * n)),
        ("r_block", (2, 2)),
        ("r_load", (2, k)),
        ("contact_force", (2, 2 * n)),
    ):
        _shape(getattr(response, name), shape, who, f"ContactResponse.{name}")
    if not response.has_block:
        for name in ("block_map", "r_base", "r_traction", "r_block", "r_load"):
            _require(
                not np.any(getattr(response, name)), who, f"{name} is zero without a loading block"
            )
    rotation = getattr(response, "rotation", None)
    if rotation is not None:
        _require(response.has_block, who, "a block rotation needs a loading block")
        for name, shape in (
            ("centre", (2,)),
            ("face_map", (n, 2)),
            ("m_traction", (2 * n,)),
            ("m_block", (2,)),
            ("m_load", (k,)),
            ("r_rotation", (2,)),
            ("contact_moment", (2 * n,)),
        ):
            _shape(np.asarray(getattr(rotation, name)), shape, who, f"BlockRotation.{name}")
        _require(
            np.isfinite(rotation.level) and np.isfinite(rotation.m_base), who, "finite rotation"
        )


def _check_contact_force(response: ContactResponse, who: str) -> np.ndarray:
    """Uniform unit traction along x (y) gives a force along x (y) only, of the face length."""
    n = response.n_nodes
    force = np.stack(
        [response.contact_force @ np.tile(unit, n) for unit in np.eye(2)], axis=1
    )  # columns: force of uniform unit traction along x, along y
    length = force[0, 0]
    _require(length > 0, who, "a uniform traction gives a positive resultant", f"{force}")
    _require(
        np.allclose(force, length * np.eye(2), rtol=0, atol=1e-10 * length),
        who,
        "the resultant of a uniform traction is along it and the same for x and y",
        f"{force}",
    )
    return response.contact_force[0, 0::2]  # node weights


def _check_energy(response: ContactResponse, weights: np.ndarray, who: str) -> None:
    """Self-equilibrated face tractions do positive work (the body is elastic and stable)."""
    rng = np.random.default_rng(7)
    n = response.n_nodes
    flexibility = response.traction_map.reshape(2 * n, 2 * n)
    weight = np.repeat(weights, 2)
    for _ in range(5):
        t = rng.standard_normal(2 * n)
        for component in range(2):  # remove the resultant of each component
            t[component::2] -= (weights @ t[component::2]) / weights.sum()
        work = (weight * t) @ (flexibility @ t)
        _require(
            work > 0,
            who,
            "an equilibrated face traction does positive work (compliance positive)",
            f"work {work:.3g}",
        )


def check_body(body_factory: Callable[[], Body], tag: str = "contact") -> None:
    """Check a body model through the :class:`~fretbem.body.Body` API.

    ``body_factory()`` returns a new body whose face ``tag`` can touch. Checked: the face
    (unit normals, shapes), unknown tags (KeyError naming them), the response (shapes,
    finite, cached, zero block parts without a block, load columns per ``load_names``), the
    face resultant of uniform tractions, positive work of equilibrated tractions,
    ``solution`` at zero and random data, and the summary facts.
    """
    body = body_factory()
    who = f"{type(body).__name__} {getattr(body, 'name', '?')!r}"
    _require(isinstance(body, Body), who, "the factory returns a Body")
    _require(isinstance(body.name, str), who, "name is a string")
    _require(isinstance(body.material, Material), who, "material is a Material")
    _require(isinstance(body.dofs, (int, np.integer)) and body.dofs > 0, who, "dofs > 0")
    _require(isinstance(body.timings, dict), who, "timings is a dict")
    _require(isinstance(body.describe(), dict), who, "describe() is a dict")
    names = tuple(body.load_names)
    _require(all(isinstance(s, str) for s in names), who, "load_names are strings")
    n = _check_face(body.contact_face(tag), who)
    try:
        body.contact_face("no such tag")
    except KeyError as error:
        _require("no such tag" in str(error), who, "an unknown tag's KeyError names it")
    else:
        raise AssertionError(f"{who}: an unknown contact tag does not raise KeyError")
    response = body.contact_response(tag)
    _require(body.contact_response(tag) is response, who, "contact_response is cached")
    _check_response(response, n, len(names), who)
    _require(
        response.has_block == (body.loading_block is not None),
        who,
        "has_block matches loading_block",
    )
    weights = _check_contact_force(response, who)
    _check_energy(response, weights, who)
    rng = np.random.default_rng(3)
    loads = {name: 1.0 for name in names}
    for tractions in (np.zeros((n, 2)), rng.standard_normal((n, 2))):
        body.solution(tag, tractions, np.zeros(2), loads)
    u = response.displacement(np.zeros((n, 2)), np.zeros(2), np.zeros(len(names)))
    _require(np.array_equal(u, response.base), who, "displacement() at zero data is the base")


def check_solver(solver, *, simulation=None) -> None:
    """Check a solver on a small contact cycle through the
    :class:`~fretbem.solvers.newton.Solver` API.

    ``simulation`` defaults to the reference scene with 21 nurbs pairs. Each increment of
    its load history must end with, at every pair to ``SOLVER_TOL`` (relative to f p0 and
    to P): p >= 0 and a closed gap where p > 0, a non-negative gap elsewhere; |q| <= f p;
    |q| = f p on slipping pairs, no slip increment on sticking pairs, nothing carried by
    separated ones; and the loading blocks carrying the prescribed forces. The reported
    states must be PairState values consistent with the tractions.
    """

    who = type(solver).__name__
    _require(isinstance(solver, Solver), who, "the solver is a Solver")
    if simulation is None:
        simulation = cattaneo_mindlin(pairs=21)
    simulation = attrs.evolve(simulation, solver=solver)
    problem = simulation.prepare()
    law = simulation.law
    friction = law.friction
    state = ContactState.initial(problem)
    p_scale = None
    for load in simulation.steps:
        forces = simulation.forces(load.normal, load.tangential)
        beta = problem.amplitudes(load.loads)
        result = solver.solve_increment(
            problem,
            law,
            forces=forces,
            loads=beta,
            previous=state,
            start=None if state.virgin else state,
        )
        step = f"{who}, step {load.name!r}"
        _require(isinstance(result, IncrementResult), step, "solve_increment returns a result")
        x = np.asarray(result.x, float)
        _shape(x, (problem.layout.size,), step, "IncrementResult.x")
        unknowns = problem.unknowns(x)
        p, q = unknowns.pressure, unknowns.shear
        p_scale = p_scale or max(np.max(p), 1e-300)
        tol = SOLVER_TOL * friction * p_scale
        normal, tangential = problem.relative(x, beta)
        gap = problem.gap + normal
        gap_scale = max(np.max(np.abs(problem.normal_map[:, problem.layout.pressure])), 1e-300)
        gap_tol = tol * gap_scale * len(p)
        _require(bool(np.all(p >= -tol)), step, "p >= 0", f"min p {p.min():.3g}")
        _require(bool(np.all(gap >= -gap_tol)), step, "no interpenetration", f"{gap.min():.3g}")
        touching = p > tol
        _require(
            bool(np.all(np.abs(gap[touching]) <= gap_tol)), step, "the gap is closed where p > 0"
        )
        _require(bool(np.all(np.abs(q) <= friction * p + tol)), step, "|q| <= f p")
        states = np.asarray(result.states)
        _require(set(np.unique(states)) <= set(PairState), step, "states are PairState values")
        slip_increment = tangential - state.slip
        slip_tol = gap_tol
        sticking = states == PairState.STICK
        slipping = states == PairState.SLIP
        _require(
            bool(np.all(np.abs(slip_increment[sticking]) <= slip_tol)),
            step,
            "sticking pairs do not slip",
        )
        _require(
            bool(np.all(np.abs(np.abs(q[slipping]) - friction * p[slipping]) <= tol)),
            step,
            "slipping pairs carry |q| = f p",
        )
        against = -np.sign(q[slipping]) * slip_increment[slipping]
        _require(
            bool(np.all(against <= slip_tol)), step, "slip opposes the shear on the lower body"
        )
        separated = states == PairState.SEPARATED
        _require(
            bool(np.all(np.abs(p[separated]) <= tol) and np.all(np.abs(q[separated]) <= tol)),
            step,
            "separated pairs carry no traction",
        )
        _, _, resultant_base = problem.bases(beta)
        resultant = resultant_base + problem.resultant_map @ x
        force_tol = SOLVER_TOL * max(np.max(np.abs(forces)), 1e-300)
        _require(
            bool(np.all(np.abs(resultant - forces) <= force_tol * 10)),
            step,
            "the loading blocks carry the prescribed forces",
            f"{resultant} against {forces}",
        )
        state = ContactState(
            x, states, tangential, load.normal, load.tangential, dict(load.loads), virgin=False
        )
