"""Discretisation error estimate of a contact run from two levels of its contact mesh.

The tractions of each level are continuous fields on the contact face (the segment's basis
times its coefficients), so one level can be evaluated at the other's pair positions. The
change between levels, scaled for an assumed rate of convergence, estimates the finer
level's error: at the finer level's points with the Richardson factor, or at the coarse
level's points (that level's own error) carried by the pair ratio to the finer level
(docs/explanation/adaptive.rst).
"""

from __future__ import annotations

import weakref

import attrs
import numpy as np

from fretbem.errors import InputError
from fretbem.verification.errors import l2

#: assumed rate of the error in the number of contact pairs for the Richardson factor of
#: :func:`estimate_errors` compared at the fine level's points (the fixed mode's default)
RATE = 3.0

#: rate of the coarse level's error carried to the fine one (``at="coarse"``, the adaptive
#: mode): aligned levels with settled knots, measured against a converged BEM on the
#: reference scene (docs/explanation/adaptive.rst)
CARRY_RATE = 2.0


class EstimateInputError(InputError):
    """Two results that cannot be compared level to level."""


@attrs.frozen(eq=False)
class TractionField:
    """p and q of one step as fields of position along the contact face (lower body).

    Attributes
    ----------
    basis : Basis
        The lower body's contact segment discretisation.
    inverse : callable
        Position along the pair tangent -> segment parameter.
    pressure, shear : ndarray
        Coefficients of p and q in the segment's basis.
    """

    basis: object
    inverse: object
    pressure: np.ndarray
    shear: np.ndarray

    def __call__(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """p(x) and q(x) at positions ``x`` along the face."""
        matrix = self.basis.evaluation_matrix(self.inverse(np.asarray(x, float)))
        return matrix @ self.pressure, matrix @ self.shear


def pair_frame(pair) -> tuple[np.ndarray, np.ndarray]:
    """Pair positions (n, 2) and tangents (n, 2) of a contact pair's pairing."""
    pairing = pair.pairing()
    return np.asarray(pairing.points, float), np.asarray(pairing.tangents, float)


def friction_of(simulation) -> float:
    """Coulomb coefficient of a simulation (its contact law, or the pair before issue 9)."""
    law = getattr(simulation, "law", None)
    return float(law.friction if law is not None else simulation.pair.friction)


def contact_segment(body, tag: str):
    """Index and discretised segment of ``body``'s contact face (:meth:`Body.face_segment`)."""
    try:
        return body.face_segment(tag)
    except InputError as err:
        raise EstimateInputError(str(err)) from None


#: per curve (weak keys) and tangent: whether its dense samples are monotonic along the
#: tangent, and their positions and parameters sorted by position
_SAMPLED: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def parameter_of(curve, tangent: np.ndarray, samples: int = 2001):
    """Inverse of the position along ``tangent`` on ``curve``: position -> parameter.

    Dense sampling, then one Newton step per point on the exact curve; the face must be
    monotonic along the tangent (a contact face is).
    """
    key = (np.asarray(tangent, float).tobytes(), samples)
    sampled = _SAMPLED.setdefault(curve, {})
    if key not in sampled:  # the faces' curves outlive the levels re-meshed on them
        grid = np.linspace(0.0, 1.0, samples)
        along = curve.points(grid) @ tangent
        monotonic = bool(np.all(np.diff(along) > 0) or np.all(np.diff(along) < 0))
        order = np.argsort(along)
        along, grid = along[order], grid[order]
        along.flags.writeable = grid.flags.writeable = False
        sampled[key] = (monotonic, along, grid)
    monotonic, along_sorted, grid_sorted = sampled[key]
    if not monotonic:
        raise EstimateInputError(
            "the contact face folds back along the pair tangent; it cannot be addressed by "
            "position along the face"
        )

    def inverse(x: np.ndarray) -> np.ndarray:
        s = np.interp(x, along_sorted, grid_sorted)
        for _ in range(2):
            s = np.clip(s, 0.0, 1.0)
            point, derivative = curve.points_and_derivatives(s)
            f = point @ tangent - x
            df = derivative @ tangent
            s = s - f / df
        return np.clip(s, 0.0, 1.0)

    return inverse


def slave_side(pair) -> str:
    """The face whose collocation points are the pairs: the one no other face is projected
    on (node to segment interpolates the other, the master); the lower for node to node."""
    masters = set(pair.pairing().interpolation)
    return "upper" if masters == {"lower"} else "lower"


def traction_fields(result) -> list[TractionField]:
    """One TractionField per step of a SimulationResult (the pairs' face: its basis)."""
    pair = result.simulation.pair
    _, basis = contact_segment(*pair.side(slave_side(pair)))
    tangent = pair_frame(pair)[1][0]
    inverse = parameter_of(basis.curve, tangent)
    params = inverse(positions(result))
    matrix = basis.evaluation_matrix(params)
    if matrix.shape[0] != matrix.shape[1]:
        raise EstimateInputError(
            f"the contact segment has {matrix.shape[1]} functions but {matrix.shape[0]} pairs; "
            "the estimate needs one collocation point per function on the contact face"
        )
    fields = []
    for step in result.steps:
        coefficients = np.linalg.solve(matrix, np.column_stack([step.pressure, step.shear]))
        fields.append(TractionField(basis, inverse, coefficients[:, 0], coefficients[:, 1]))
    return fields


def positions(result) -> np.ndarray:
    """Pair positions along the pair tangent (x in the reference scene)."""
    points, tangents = pair_frame(result.simulation.pair)
    return points @ tangents[0]


def scales(result) -> tuple[float, float]:
    """Normalising tractions (p0, f p0): the reference's, else the peak pressure of the run."""
    reference = result.simulation.reference
    friction = friction_of(result.simulation)
    if reference is not None:
        p0 = reference.hertz.peak_pressure
    else:
        p0 = max(float(np.max(s.pressure)) for s in result.steps)
    return p0, friction * p0


def difference(coarse, fine, *, at: str = "fine") -> list[dict[str, float]]:
    """Per step: max and L2 of p and q change between two levels, in units of p0 and f p0.

    Compared at the pair positions of the ``fine`` level (the other level's field evaluated
    there), or of the ``coarse`` one with ``at="coarse"`` (the error of a level at its own
    collocation points against a finer reference).
    """
    if [s.name for s in coarse.steps] != [s.name for s in fine.steps]:
        raise EstimateInputError(
            "the two results have different load steps; compare two levels of one history"
        )
    if at not in ("fine", "coarse"):
        raise EstimateInputError(f"difference(at=...) is 'fine' or 'coarse', got {at!r}")
    p0, fp0 = scales(fine)
    nodes, other = (fine, coarse) if at == "fine" else (coarse, fine)
    x = positions(nodes)
    order = np.argsort(x)
    out = []
    for field, step in zip(traction_fields(other), nodes.steps, strict=True):
        po, qo = field(x)
        dp = np.abs(step.pressure - po)[order]
        dq = np.abs(step.shear - qo)[order]
        out.append(
            {
                "p_max": float(dp.max() / p0),
                "q_max": float(dq.max() / fp0),
                "p_l2": l2(dp, x[order]) / p0,
                "q_l2": l2(dq, x[order]) / fp0,
            }
        )
    return out


def _pair_ratio(coarse_pairs: int, fine_pairs: int) -> float:
    ratio = fine_pairs / coarse_pairs
    if ratio <= 1.0:
        raise EstimateInputError(
            f"the fine level has {fine_pairs} pairs, not more than the coarse level's "
            f"{coarse_pairs}; pass (coarse, fine) in that order with more pairs in the fine one"
        )
    return ratio


def richardson_factor(coarse_pairs: int, fine_pairs: int, rate: float = RATE) -> float:
    """Error of the finer level over the change between levels, for error ~ pairs^-rate."""
    return 1.0 / (_pair_ratio(coarse_pairs, fine_pairs) ** rate - 1.0)


def carry_factor(coarse_pairs: int, fine_pairs: int, rate: float = CARRY_RATE) -> float:
    """Error of the finer level over the coarse level's, for error ~ pairs^-rate."""
    return _pair_ratio(coarse_pairs, fine_pairs) ** (-rate)


def estimate_errors(
    coarse, fine, *, rate: float | None = None, at: str = "fine"
) -> dict[str, dict[str, float]]:
    """Estimated discretisation error of ``fine`` per step, from a coarser level ``coarse``.

    Returns ``{step name: {"e_p_max", "e_q_max", "e_p_l2", "e_q_l2"}}`` as fractions of p0
    and f p0 (the keys of ``StepResult.errors``). ``at="fine"``: the change between the
    levels at the fine level's points times :func:`richardson_factor` (rate default
    :data:`RATE`). ``at="coarse"``: the change at the coarse level's points, which is the
    coarse level's own error, times :func:`carry_factor` (rate default :data:`CARRY_RATE`;
    the adaptive mode's levels). Both results must be of the same history and face.
    """
    n_coarse, n_fine = coarse.steps[0].x.size, fine.steps[0].x.size
    if at == "coarse":
        factor = carry_factor(n_coarse, n_fine, CARRY_RATE if rate is None else rate)
    else:
        factor = richardson_factor(n_coarse, n_fine, RATE if rate is None else rate)
    out = {}
    for step, change in zip(fine.steps, difference(coarse, fine, at=at), strict=True):
        out[step.name] = {f"e_{k}": factor * v for k, v in change.items()}
    return out
