"""Generalized (semi-smooth) Newton method for frictional contact on the condensed problem.

Contact conditions are written as nonlinear complementarity functions (Alart-Curnier):
    F_n = p - max(0, p - r g),   F_t = q - proj[-f p^, f p^](q + r s),   p^ = max(0, p - r g)
with g the deformed gap and s the tangential slip increment. They are piecewise linear, so
each Newton step solves the exact linear problem of its separated/stick/slip pattern, and
the iteration ends when the residual is below the tolerance, which happens once the
pattern is right (docs/theory.md).
"""

from __future__ import annotations

import attrs
import numpy as np
from threadpoolctl import threadpool_limits

from .contact import SEPARATED, SLIP, STATE_NAMES, STICK, CondensedContact

#: factor applied to the normal augmentation r_n when the Newton iteration cycles
CYCLE_SOFTENING = 0.1


class NewtonConvergenceError(RuntimeError):
    """The Newton iteration did not converge; carries the residual history and culprits.

    Attributes
    ----------
    residuals : list of float
    changing_pairs : ndarray of int
        Pairs whose contact state changed during the last iterations.
    """

    def __init__(self, message: str, residuals, changing_pairs):
        super().__init__(message)
        self.residuals = list(residuals)
        self.changing_pairs = np.asarray(changing_pairs)


@attrs.frozen(eq=False)
class IncrementResult:
    """Converged pair unknowns x = (p, q, deltas), states and iteration history."""

    x: np.ndarray
    states: np.ndarray
    iterations: int
    residuals: tuple[float, ...]


@attrs.frozen
class Solver:
    """Semi-smooth Newton solver settings.

    Attributes
    ----------
    tolerance : float
        Relative tolerance on the complementarity and equilibrium residuals.
    max_iterations : int
        Newton iterations per increment before giving up (or sub-stepping).
    max_substeps : int
        Times a failing increment may be halved automatically (0 disables sub-stepping).
    """

    tolerance: float = attrs.field(default=1e-10, converter=float)
    max_iterations: int = attrs.field(default=50, converter=int)
    max_substeps: int = attrs.field(default=4, converter=int)

    def _evaluate(self, problem: CondensedContact, friction, forces, reference_slip, x, r_n, r_t):
        n = problem.n_pairs
        p, q = x[:n], x[n : 2 * n]
        gap = problem.gap + problem.normal_base + problem.normal_map @ x
        slip = problem.tangential_base + problem.tangential_map @ x - reference_slip
        augmented = p - r_n * gap
        contact = augmented > 0
        trial = q + r_t * slip
        bound = friction * np.maximum(augmented, 0.0)
        stick = contact & (np.abs(trial) < bound)
        sliding = contact & ~stick
        direction = np.sign(trial)
        f_n = np.where(contact, r_n * gap, p)
        f_t = np.where(stick, -r_t * slip, np.where(sliding, q - bound * direction, q))
        f_b = problem.resultant_base + problem.resultant_map @ x - forces
        states = np.full(n, SEPARATED)
        states[stick], states[sliding] = STICK, SLIP
        return np.concatenate([f_n, f_t, f_b]), states, direction

    def _jacobian(self, problem, friction, states, direction, r_n, r_t):
        n = problem.n_pairs
        n_x = problem.normal_map.shape[1]
        jac = np.zeros((n_x, n_x))
        rows = np.arange(n)
        separated, stick, slip = (states == s for s in (SEPARATED, STICK, SLIP))
        contact = ~separated
        jac[rows[separated], rows[separated]] = 1.0
        jac[rows[contact]] = r_n * problem.normal_map[contact]
        jac[n + rows[separated], n + rows[separated]] = 1.0
        jac[n + rows[stick]] = -r_t * problem.tangential_map[stick]
        slip_rows = n + rows[slip]
        coeff = (friction * direction[slip])[:, None]
        jac[slip_rows] = coeff * r_n * problem.normal_map[slip]
        jac[slip_rows, rows[slip]] -= coeff[:, 0]
        jac[slip_rows, slip_rows] += 1.0
        jac[2 * n :] = problem.resultant_map
        return jac

    def solve_increment(
        self,
        problem: CondensedContact,
        *,
        friction: float,
        forces: np.ndarray,
        reference_slip: np.ndarray,
        start: np.ndarray | None = None,
        start_states: np.ndarray | None = None,
    ) -> IncrementResult:
        """Solve one load increment from ``start`` (the gap-only start x = 0 if None).

        BLAS runs single-threaded here: the Newton systems are small (2 n + 2 unknowns), and
        threads competing for the cores of a busy machine made each solve 10-40x slower
        (benchmarks/performance.py: 1.65 s against 0.29 s for the 61-pair cycle).
        """
        with threadpool_limits(limits=1, user_api="blas"):
            return self._solve_increment(
                problem, friction, forces, reference_slip, start, start_states
            )

    def _solve_increment(
        self, problem, friction, forces, reference_slip, start, start_states
    ) -> IncrementResult:
        """The Newton iteration of :meth:`solve_increment`.

        From the gap-only start every pair is first taken closed and sticking, which makes
        the first linear system non-singular even for a body held only by contact.
        """
        n = problem.n_pairs
        n_x = problem.normal_map.shape[1]
        r_n = 1.0 / np.mean(np.abs(np.diag(problem.normal_map[:, :n])))
        r_t = 1.0 / np.mean(np.abs(np.diag(problem.tangential_map[:, n : 2 * n])))
        x = np.zeros(n_x) if start is None else np.array(start, dtype=float)
        forces = np.asarray(forces, float)
        residual, states, direction = self._evaluate(
            problem, friction, forces, reference_slip, x, r_n, r_t
        )
        if start is None or start_states is None:
            states = np.full(n, STICK)
        else:
            states = np.asarray(start_states)
        history, state_history, seen = [], [states.copy()], set()
        force_scale = max(np.max(np.abs(forces), initial=0.0), 1e-300)
        for iteration in range(1, self.max_iterations + 1):
            jac = self._jacobian(problem, friction, states, direction, r_n, r_t)
            try:
                step = np.linalg.solve(jac, -residual)
            except np.linalg.LinAlgError:
                step = np.linalg.lstsq(jac, -residual, rcond=None)[0]
            x = x + step
            residual, new_states, direction = self._evaluate(
                problem, friction, forces, reference_slip, x, r_n, r_t
            )
            traction_scale = max(np.max(np.abs(x[: 2 * n])), 1e-300)
            norm = max(
                np.max(np.abs(residual[: 2 * n])) / traction_scale,
                np.max(np.abs(residual[2 * n :]), initial=0.0) / force_scale,
            )
            history.append(float(norm))
            states = new_states
            state_history.append(states.copy())
            # F is continuous across the separated/stick/slip boundaries, so a small residual
            # is a solution whichever side round-off puts a pair on. Pairs exactly at a limit
            # (|q| = f p with zero slip increment) flip state at round-off; requiring the
            # pattern to stop changing exhausted the iterations on dissimilar bodies.
            if norm <= self.tolerance:
                return IncrementResult(x, states, iteration, tuple(history))
            # F is affine on each pattern (states, slip directions), so the Newton iterate
            # depends on the pattern only: a pattern seen before means an endless cycle.
            # Break it by softening the normal augmentation r_n (F keeps the same roots).
            pattern = (states.tobytes(), np.where(states == SLIP, direction, 0.0).tobytes())
            if pattern in seen:
                seen.clear()
                r_n *= CYCLE_SOFTENING
                residual, states, direction = self._evaluate(
                    problem, friction, forces, reference_slip, x, r_n, r_t
                )
            else:
                seen.add(pattern)
        recent = np.array(state_history[-6:])
        changing = np.flatnonzero(np.any(recent != recent[-1], axis=0))
        raise NewtonConvergenceError(
            f"the contact Newton iteration did not converge in {self.max_iterations} iterations "
            f"(last residual {history[-1]:.3g}, tolerance {self.tolerance:.1g}); pairs "
            f"{changing.tolist()} kept changing state "
            f"({', '.join(STATE_NAMES[s] for s in np.unique(recent[:, changing]))}). Split the "
            "load step into sub-increments (LoadStep(increments=...)), allow automatic "
            "sub-stepping (Solver(max_substeps=...)), or refine the contact discretisation",
            history,
            changing,
        )
