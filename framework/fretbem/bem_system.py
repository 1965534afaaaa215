"""The factorised collocation system of a BEM body and its condensed contact response.

H u = G t with the prescribed data moved right is factorised once per set of contact
segments; the loading-block displacement, the named load amplitudes and the contact
traction coefficients stay parameters, so every later solve is a triangular solve and
the contact response (:class:`~fretbem.body.ContactResponse`) is a few matrix products.
"""

from __future__ import annotations

import time
from typing import TYPE_CHECKING

import attrs
import numpy as np
import scipy.linalg as sla

from ._blas import one_blas_thread
from .bem_layout import BLOCK, CONTACT, DISPLACEMENT, TRACTION
from .body import ContactResponse, RigidMotionError

if TYPE_CHECKING:  # pragma: no cover
    from .bem_body import BemBody


class BodySystem:
    """H u = G t with prescribed data moved right, factorised once.

    Unknowns z: u where traction is known (and on contact segments), t where displacement is
    known (and on the loading block). The loading-block displacement delta, the load
    amplitudes beta and the contact traction coefficients stay parameters:
    z = z0 + Z_delta delta + Z_beta beta + Z_contact t_contact.
    """

    def __init__(self, body: BemBody, contact_tags: tuple[str, ...]):
        self.body = body
        h, g = body.matrices()
        start = time.perf_counter()
        layout = body.layout(contact_tags)
        self.kinds, self.known = layout.kinds.ravel(), layout.known.ravel()
        self.load_known = layout.loads.reshape(len(layout.loads), self.kinds.size)  # (k, 2N)
        solves_u = (self.kinds == TRACTION) | (self.kinds == CONTACT)
        self.solves_u = solves_u
        matrix = np.where(solves_u[None, :], h, -g)
        fixed_u, fixed_t = self.kinds == DISPLACEMENT, self.kinds == TRACTION
        rhs = -h[:, fixed_u] @ self.known[fixed_u]
        rhs += g[:, fixed_t] @ self.known[fixed_t]
        load_rhs = g[:, fixed_t] @ self.load_known[:, fixed_t].T  # (2N, k)
        self.block_dofs = np.flatnonzero(self.kinds == BLOCK)
        block_columns = np.zeros((len(self.kinds), 2))
        block_columns[self.block_dofs, self.block_dofs % 2] = 1.0
        self.contact_dofs = np.flatnonzero(self.kinds == CONTACT)
        k = load_rhs.shape[1]
        parameters = np.column_stack([rhs, -h @ block_columns, g[:, self.contact_dofs], load_rhs])
        with one_blas_thread():  # a busy machine made threaded BLAS 60x slower here
            self.factor = sla.lu_factor(matrix, overwrite_a=True, check_finite=False)
            response = sla.lu_solve(self.factor, parameters, overwrite_b=True, check_finite=False)
        if not np.all(np.isfinite(response)):
            raise RigidMotionError(
                f"body {body.name!r}: the collocation system is singular; check that the "
                "boundary conditions fix the rigid motions"
            )
        self.base = response[:, 0]
        self.block_response = response[:, 1:3]
        self.contact_response = response[:, 3 : response.shape[1] - k]
        self.load_response = response[:, response.shape[1] - k :]
        body.timings["factorisation"] = time.perf_counter() - start

    def unknowns(self, delta, contact_tractions, loads=()) -> np.ndarray:
        """z = z0 + Z_delta delta + Z_contact t_contact + Z_beta beta."""
        beta = np.asarray(loads, float).reshape(-1)
        return (
            self.base
            + self.block_response @ np.asarray(delta, float)
            + self.contact_response @ np.asarray(contact_tractions, float)
            + self.load_response @ beta
        )

    def block_resultant(self, z: np.ndarray) -> np.ndarray:
        """Resultant force (2, ...) of the loading block's tractions in unknown vector(s) z."""
        weights = np.repeat(self.body.resultant_weights(), 2)[self.block_dofs]
        select = np.zeros((2, len(self.block_dofs)))
        select[self.block_dofs % 2, np.arange(len(self.block_dofs))] = weights
        return select @ z[self.block_dofs]

    def resultant_map(self) -> tuple[np.ndarray, np.ndarray]:
        """Block resultant force as r0 + K delta (with zero contact traction and loads)."""
        return self.block_resultant(self.base), self.block_resultant(self.block_response)

    def solution(self, delta, contact_tractions, loads=()) -> BodySolution:
        """Full displacement and traction coefficients for given block, contact and loads."""
        beta = np.asarray(loads, float).reshape(-1)
        delta = np.asarray(delta, float)
        z = self.unknowns(delta, contact_tractions, beta)
        known = self.known + beta @ self.load_known if beta.size else self.known
        u = np.where(self.solves_u, z, known)
        t = np.where(self.solves_u, known, z)
        u[self.block_dofs] = delta[self.block_dofs % 2]
        t[self.contact_dofs] = contact_tractions
        return BodySolution(self.body, u.reshape(-1, 2), t.reshape(-1, 2), delta)


def face_rows(body: BemBody, tag: str) -> tuple[np.ndarray, np.ndarray]:
    """Collocation rows and global function indices of the segments tagged ``tag``."""
    segments = sorted(body._indices(tag, "the contact pair"))
    rows = np.flatnonzero(np.isin(body.collocation.segment, segments))
    functions = np.concatenate(
        [np.arange(*body.function_slice(k).indices(body.n_functions)) for k in segments]
    )
    return rows, functions


def face_values_matrix(body: BemBody, tag: str) -> np.ndarray:
    """E of the contact face: coefficients to values at its collocation points (block diag)."""
    segments = sorted(body._indices(tag, "the contact pair"))
    sizes = [body.segments[k].n_functions for k in segments]
    e_matrix = np.zeros((sum(sizes), sum(sizes)))
    start = 0
    for k, n in zip(segments, sizes, strict=True):
        e_matrix[start : start + n, start : start + n] = body.segments[k].collocation_matrix()
        start += n
    return e_matrix


def contact_response(body: BemBody, tag: str) -> ContactResponse:
    """The face's displacement at its collocation points, affine in node tractions.

    Node traction values t become coefficients C t (C = E^-1); the system gives the
    face's displacement coefficients; E turns them back into node values. Only BLAS
    matrix products on (n, 2 N)-sized blocks.
    """
    system = body.system((tag,))
    e_matrix = face_values_matrix(body, tag)
    n = len(e_matrix)
    inverse = np.linalg.solve(e_matrix, np.eye(n))  # coefficient a per unit value at node b

    def node_values(z: np.ndarray) -> np.ndarray:
        """Displacement values (n, 2, cols) at the face nodes from unknown columns z."""
        cols = z.shape[1]
        coefficients = z[system.contact_dofs].reshape(n, 2 * cols)
        return (e_matrix @ coefficients).reshape(n, 2, cols)

    # contact response per unit node traction: columns (b, j) <- sum_a Z[:, (a, j)] C[a, b]
    z_contact = system.contact_response.reshape(-1, n, 2).transpose(0, 2, 1)
    z_traction = (z_contact.reshape(-1, n) @ inverse).reshape(-1, 2, n)
    z_traction = z_traction.transpose(0, 2, 1).reshape(-1, 2 * n)
    weights = body.resultant_weights()[face_rows(body, tag)[1]] @ inverse  # force per node
    contact_force = np.zeros((2, 2 * n))
    contact_force[0, 0::2] = weights
    contact_force[1, 1::2] = weights
    k = system.load_response.shape[1]
    has_block = bool(system.block_dofs.size)
    if has_block:
        r_base, r_traction, r_block, r_load = (
            system.block_resultant(z)
            for z in (system.base, z_traction, system.block_response, system.load_response)
        )
    else:
        r_base, r_traction = np.zeros(2), np.zeros((2, 2 * n))
        r_block, r_load = np.zeros((2, 2)), np.zeros((2, k))
    return ContactResponse(
        base=node_values(system.base[:, None])[:, :, 0],
        traction_map=node_values(z_traction),
        block_map=node_values(system.block_response) if has_block else np.zeros((n, 2, 2)),
        load_map=node_values(system.load_response),
        r_base=r_base,
        r_traction=r_traction,
        r_block=r_block,
        r_load=r_load.reshape(2, k),
        contact_force=contact_force,
        has_block=has_block,
    )


@attrs.frozen(eq=False)
class BodySolution:
    """Displacement and traction coefficients of a solved BEM body.

    Attributes
    ----------
    body : BemBody
    displacement_coefficients, traction_coefficients : ndarray, shape (N, 2)
    block_displacement : ndarray, shape (2,)
    """

    body: BemBody
    displacement_coefficients: np.ndarray
    traction_coefficients: np.ndarray
    block_displacement: np.ndarray

    def _field(self, coefficients, segment: int, params) -> np.ndarray:
        basis = self.body.segments[segment]
        return basis.evaluation_matrix(params) @ coefficients[self.body.function_slice(segment)]

    def displacement(self, segment: int, params) -> np.ndarray:
        """Displacement (m, 2) at curve parameters of one segment."""
        return self._field(self.displacement_coefficients, segment, params)

    def traction(self, segment: int, params) -> np.ndarray:
        """Traction (m, 2) at curve parameters of one segment."""
        return self._field(self.traction_coefficients, segment, params)

    def points(self, segment: int, params) -> np.ndarray:
        """Positions (m, 2) of the discretised geometry at curve parameters."""
        basis = self.body.segments[segment]
        return basis.geometry(*basis.to_local(params))[0]
