"""Loading by force or by displacement: the loading block's equations for each control.

Under force control the upper body's loading block carries the prescribed force
(-P n + Q t). Under displacement control one of its two resultant equations is replaced
by a constraint on the block's own displacement, measured against a datum:

- tangential: delta = t . (u_block(upper) - u_block(lower)), the pad's block against the
  specimen's held end (a specimen without a loading block is held: its block displacement
  is 0); Q is then an output;
- normal: the approach alpha = -n . (u_block(upper) - u_block(lower)) (> 0 presses); P is
  then an output.

The replaced rows are scaled by a contact stiffness, so that the solvers' force-relative
residual measures them in force units too. A controlled problem is the same
:class:`~fretbem.contact.condensation.CondensedContact` with other resultant rows, so every
solver takes it unchanged.
"""

from __future__ import annotations

import attrs
import numpy as np

from .condensation import CondensedContact

#: the two controls of a loading-block direction
CONTROLS = ("force", "displacement")


@attrs.frozen
class Controls:
    """Which loading-block directions are driven by displacement.

    Attributes
    ----------
    normal : str
        ``"force"`` (P imposed) or ``"displacement"`` (the approach imposed).
    tangential : str
        ``"force"`` (Q imposed) or ``"displacement"`` (delta imposed).
    """

    normal: str = attrs.field(default="force", validator=attrs.validators.in_(CONTROLS))
    tangential: str = attrs.field(default="force", validator=attrs.validators.in_(CONTROLS))

    @property
    def by_force(self) -> bool:
        """True when both directions are force controlled (the problem is unchanged)."""
        return self.normal == "force" and self.tangential == "force"


def frame(problem: CondensedContact) -> tuple[np.ndarray, np.ndarray]:
    """Mean normal n and tangent t of the pair: the loads and the block motion act along them."""
    normal = problem.pairing.normals.mean(axis=0)
    normal = normal / np.linalg.norm(normal)
    return normal, np.array([normal[1], -normal[0]])


def _block_rows(problem: CondensedContact) -> slice:
    blocks = problem.blocks
    start = 2 * blocks.index("upper")
    return slice(start, start + 2)


def motion_rows(problem: CondensedContact) -> np.ndarray:
    """(2, n_x): approach and delta of the pad's block against the datum, per unit x."""
    n, t = frame(problem)
    layout = problem.layout
    rows = np.zeros((2, layout.size))
    rows[0, layout.block("upper")] = -n
    rows[1, layout.block("upper")] = t
    if "lower" in problem.blocks:
        rows[0, layout.block("lower")] = n
        rows[1, layout.block("lower")] = -t
    return rows


def stiffness(problem: CondensedContact) -> float:
    """A tangential contact stiffness (force per thickness per mm): the scale of the rows."""
    layout = problem.layout
    weights = np.abs(problem.resultant_map[_block_rows(problem), layout.tractions]).sum(axis=1)
    compliance = np.mean(np.abs(np.diag(problem.tangential_map[:, layout.shear])))
    return float(max(weights.max(initial=0.0), 1e-300) / max(compliance, 1e-300))


def measure(problem: CondensedContact, x: np.ndarray, beta: np.ndarray = ()) -> dict:
    """P, Q, approach and delta of the pad's block at pair unknowns x (force-control problem)."""
    n, t = frame(problem)
    _, _, base = problem.bases(np.asarray(beta, float))
    force = (base + problem.resultant_map @ x)[_block_rows(problem)]
    approach, delta = motion_rows(problem) @ x
    return {
        "normal": float(-force @ n),
        "tangential": float(force @ t),
        "approach": float(approach),
        "delta": float(delta),
    }


def controlled(problem: CondensedContact, controls: Controls) -> CondensedContact:
    """``problem`` with the pad block's resultant rows replaced as ``controls`` says.

    The two rows of the upper block become (P row or k x approach row, Q row or k x delta
    row), in the pair frame; :func:`targets` gives the values they must reach.
    """
    if controls.by_force:
        return problem
    n, t = frame(problem)
    rows = _block_rows(problem)
    k = stiffness(problem)
    motion = motion_rows(problem) * k
    resultant_map = problem.resultant_map.copy()
    resultant_base = problem.resultant_base.copy()
    resultant_load = problem.resultant_load.copy()
    block_map = problem.resultant_map[rows]
    block_base = problem.resultant_base[rows]
    block_load = problem.resultant_load[rows]
    for i, (control, direction, sign) in enumerate(
        ((controls.normal, n, -1.0), (controls.tangential, t, 1.0))
    ):
        row = rows.start + i
        if control == "force":
            resultant_map[row] = sign * direction @ block_map
            resultant_base[row] = sign * direction @ block_base
            resultant_load[row] = sign * direction @ block_load
        else:
            resultant_map[row] = motion[i]
            resultant_base[row] = 0.0
            resultant_load[row] = 0.0
    return attrs.evolve(
        problem,
        resultant_map=resultant_map,
        resultant_base=resultant_base,
        resultant_load=resultant_load,
    )


def targets(
    problem: CondensedContact, controls: Controls, normal: float, tangential: float, forces
) -> np.ndarray:
    """The values the resultant rows of ``controlled(problem, controls)`` must reach.

    ``normal`` is P or the approach, ``tangential`` Q or delta, as ``controls`` says;
    ``forces`` are the force-control targets of every block (returned as they are when both
    directions are force controlled).
    """
    forces = np.array(forces, dtype=float)
    if controls.by_force:
        return forces
    k = stiffness(problem)
    rows = _block_rows(problem)
    forces[rows.start] = normal if controls.normal == "force" else k * normal
    forces[rows.start + 1] = tangential if controls.tangential == "force" else k * tangential
    return forces
