"""Dissimilar cylinders in partial slip: an independent half-plane reference with Dundurs' beta.

When the two bodies differ elastically (Dundurs' beta != 0), pressure and shear couple: a
normal load alone makes the surfaces slide inward by different amounts, so friction acts
before any tangential load (Goodman 1962). Spence (1975) showed that under a monotonically
growing Hertz load the solution is self-similar: a central stick zone |x| < c whose ratio
c/a depends only on beta/f, slip outward of it. No closed form gives the tractions, so this
module computes them independently of fretbem's solvers: two half-planes, tractions
piecewise constant on a uniform grid of cells, exact influence integrals of Flamant's line
loads (Johnson, Contact Mechanics, eqs. 2.19-2.20), collocation at the cell centres, and an
incremental active-set solution (normal contact and stick/slip alternated to convergence
with the full coupling, not Goodman's approximation). Its error falls like the cell width.
A bulk stress in the specimen is accepted too (similar or dissimilar bodies), which makes it
a reference beyond the Nowell-Hills limit, where slip reverses at one edge and no closed
form exists; inside the limit it reproduces Nowell-Hills to 0.1 % of f p0 (400 cells).

Conventions as :mod:`fretbem.verification.closed_forms`: body 1 is the upper body (pad),
body 2 the lower (specimen); p >= 0; q is the shear the upper body exerts on the lower, in
+x, so that sum(p) dx = P and sum(q) dx = Q; mm, N/mm, MPa.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import attrs
import numpy as np

from fretbem.validators import number_field, poisson_ratio, positive_field

from .closed_forms import HertzLineContact, dundurs_beta, effective_modulus
from .nowell_hills import NotApplicableError

__all__ = ["DissimilarCylinders", "DissimilarState", "reference_for_scene", "stick_half_width"]

SEPARATED, STICK, SLIP = 0, 1, 2


@attrs.frozen(eq=False)
class DissimilarState:
    """Tractions at the end of one load step of :meth:`DissimilarCylinders.solve`.

    Attributes
    ----------
    normal, tangential : float
        P and Q at the end of the step.
    x : ndarray
        Cell centres.
    pressure, shear : ndarray
        p and q per cell.
    states : ndarray of int
        0 separated, 1 stick, 2 slip (the codes of fretbem's pair states).
    """

    normal: float
    tangential: float
    x: np.ndarray
    pressure: np.ndarray
    shear: np.ndarray
    states: np.ndarray


def stick_half_width(x: np.ndarray, states: np.ndarray) -> float:
    """Half-width of the central stick zone: mean of its two outer edges (cell-centre based).

    Each edge is taken midway between the outermost sticking cell and its outward neighbour.
    """
    stick = np.flatnonzero(states == STICK)
    if stick.size == 0:
        return 0.0
    h = float(x[1] - x[0])
    return 0.5 * ((x[stick.max()] + 0.5 * h) - (x[stick.min()] - 0.5 * h))


def _influence(x: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray]:
    """Integrals over each cell j of ln|x_i - s| and of sign(x_i - s) ds."""
    lo = x - 0.5 * h
    hi = x + 0.5 * h

    def g(t):
        t = np.asarray(t)
        with np.errstate(divide="ignore", invalid="ignore"):
            out = t * np.log(np.abs(t)) - t
        return np.where(t == 0.0, 0.0, out)

    t_lo = x[:, None] - lo[None, :]
    t_hi = x[:, None] - hi[None, :]
    log = g(t_lo) - g(t_hi)
    clipped = np.clip(x[:, None], lo[None, :], hi[None, :])
    sign = (clipped - lo[None, :]) - (hi[None, :] - clipped)
    return log, sign


def _poisson(what: str) -> attrs.Converter:
    return number_field(what, "give nu in (-1, 0.5)", check=poisson_ratio)


@attrs.frozen
class DissimilarCylinders:
    """Two elastically dissimilar half-planes with a Hertzian gap, loaded by (P, Q) paths.

    Attributes
    ----------
    radius : float
        R_eff with 1/R_eff = 1/R1 + 1/R2 (gap x^2 / (2 R_eff)).
    E_upper, nu_upper, E_lower, nu_lower : float
        Elastic constants of the pad (upper) and the specimen (lower).
    friction : float
        Coulomb coefficient f.
    plane_stress : bool
        Plane stress instead of plane strain.
    """

    radius: float = attrs.field(
        converter=positive_field("R_eff, mm", "give 1 / (1/R1 + 1/R2) in mm")
    )
    E_upper: float = attrs.field(
        converter=positive_field("the pad's Young's modulus, MPa", "give E")
    )
    nu_upper: float = attrs.field(converter=_poisson("the pad's Poisson's ratio"))
    E_lower: float = attrs.field(
        converter=positive_field("the specimen's Young's modulus, MPa", "give E")
    )
    nu_lower: float = attrs.field(converter=_poisson("the specimen's Poisson's ratio"))
    friction: float = attrs.field(
        converter=positive_field("the Coulomb coefficient f", "give f > 0 (e.g. 0.3 to 1.5)")
    )
    plane_stress: bool = False

    # ---------------------------------------------------------------- elastic constants
    def _constants(self, E: float, nu: float) -> tuple[float, float]:
        """(A, B): surface u = -A ln|x| F (along F) and B sign(x) F (across), per line load."""
        if self.plane_stress:
            return 2.0 / (math.pi * E), (1.0 - nu) / (2.0 * E)
        return 2.0 * (1.0 - nu**2) / (math.pi * E), (1.0 - 2.0 * nu) * (1.0 + nu) / (2.0 * E)

    @property
    def beta(self) -> float:
        """Dundurs' beta of the pad against the specimen."""
        return dundurs_beta(self.E_upper, self.nu_upper, self.E_lower, self.nu_lower,
                            plane_stress=self.plane_stress)  # fmt: skip

    def hertz(self, load: float) -> HertzLineContact:
        """The Hertz contact at P = load (the pressure Goodman's approximation assumes)."""
        modulus = effective_modulus(self.E_upper, self.nu_upper, self.E_lower, self.nu_lower,
                                    plane_stress=self.plane_stress)  # fmt: skip
        return HertzLineContact(load, self.radius, modulus)

    # ---------------------------------------------------------------- solution
    def solve(
        self,
        history: Sequence[tuple[float, ...]],
        *,
        cells: int = 400,
        half_width: float | None = None,
        increments: int | Sequence[int] = 40,
        tolerance: float = 1e-10,
    ) -> list[DissimilarState]:
        """Tractions after each (P, Q) or (P, Q, sigma_B) of ``history``, reached linearly.

        sigma_B is a uniform bulk stress along x in the lower body (the specimen) at infinity,
        tension > 0: it stretches the specimen's surface by (1 - nu^2) sigma_B / E (plane
        strain), which adds to the relative tangential displacement (Nowell and Hills 1987).

        ``cells`` uniform cells cover |x| < ``half_width`` (1.3 Hertz half-widths at the
        largest P by default); ``increments`` per step (one number or one per step): the
        normal loading of dissimilar bodies is path dependent and needs many.
        """
        history = [(float(h[0]), float(h[1]), float(h[2]) if len(h) > 2 else 0.0)
                   for h in history]  # fmt: skip
        if not history or history[0][0] <= 0:
            raise ValueError("the history must start with a positive normal load P")
        if any(abs(q) >= self.friction * p for p, q, _ in history):
            raise ValueError("every step needs |Q| < f P (otherwise gross sliding)")
        steps = [increments] * len(history) if isinstance(increments, int) else list(increments)
        largest = max(p for p, _, _ in history)
        L = half_width or 1.3 * self.hertz(largest).half_width
        h = 2.0 * L / cells
        x = -L + h * (np.arange(cells) + 0.5)
        log, sign = _influence(x, h)
        A1, B1 = self._constants(self.E_upper, self.nu_upper)
        A2, B2 = self._constants(self.E_lower, self.nu_lower)
        A, B = A1 + A2, B2 - B1
        gap0 = x**2 / (2.0 * self.radius)
        # normal: g = gap0 - delta - A log p + B sign q; tangential: s = B sign p + A log q - d
        N = -A * log
        T = A * log
        f = self.friction
        stretch = (
            1.0 / self.E_lower if self.plane_stress else (1.0 - self.nu_lower**2) / self.E_lower
        ) * x

        p = np.zeros(cells)
        q = np.zeros(cells)
        d = 0.0
        states = np.zeros(cells, dtype=int)
        slide = np.zeros(cells)  # slip direction of slipping cells
        out = []
        previous = (0.0, 0.0, 0.0)
        bulk_old = 0.0
        for (P, Q, S), n in zip(history, steps, strict=True):
            for k in range(1, n + 1):
                load = previous[0] + (P - previous[0]) * k / n
                shear_load = previous[1] + (Q - previous[1]) * k / n
                bulk = previous[2] + (S - previous[2]) * k / n
                s_old = B * (sign @ p) + T @ q - d - bulk_old * stretch
                for _ in range(200):
                    p_new = self._normal(N, gap0 + B * (sign @ q), h, load, p)
                    offset = B * (sign @ p_new) - bulk * stretch
                    q_new, d, states, slide = self._tangential(
                        T, offset, s_old, h, shear_load, p_new, states, slide, f, q
                    )
                    change = max(np.abs(p_new - p).max(), np.abs(q_new - q).max())
                    p, q = p_new, q_new
                    if change <= tolerance * max(np.abs(p).max(), 1e-300):
                        break
                else:
                    raise RuntimeError("the normal-tangential coupling did not converge")
                bulk_old = bulk
            previous = (P, Q, S)
            out.append(DissimilarState(P, Q, x.copy(), p.copy(), q.copy(), states.copy()))
        return out

    @staticmethod
    def _normal(N, rhs, h, load, p_start) -> np.ndarray:
        """Frictionless active set: gap rhs - delta + N p >= 0, p >= 0, sum p h = load."""
        n = rhs.size
        active = p_start > 0
        if not active.any():
            active = rhs <= np.sort(rhs)[min(4, n - 1)]
        for _ in range(500):
            idx = np.flatnonzero(active)
            m = idx.size
            K = np.zeros((m + 1, m + 1))
            K[:m, :m] = N[np.ix_(idx, idx)]
            K[:m, m] = -1.0
            K[m, :m] = h
            sol = np.linalg.solve(K, np.concatenate([-rhs[idx], [load]]))
            p = np.zeros(n)
            p[idx] = sol[:m]
            gap = rhs - sol[m] + N @ p
            negative = active & (p < 0)
            penetrating = ~active & (gap < -1e-14 * max(abs(sol[m]), 1e-300))
            if not negative.any() and not penetrating.any():
                return np.where(active, np.maximum(p, 0.0), 0.0)
            active = (active & ~negative) | penetrating
        raise RuntimeError("the normal active set did not converge")

    @staticmethod
    def _tangential(T, offset, s_old, h, load, p, states, slide, f, q_start):
        """Stick/slip active set of one increment for the pressure p (touching cells p > 0)."""
        n = p.size
        touching = p > 0
        states = np.where(touching, np.where(states == SEPARATED, STICK, states), SEPARATED)
        slide = np.where(states == SLIP, slide, 0.0)
        seen = set()
        for _ in range(500):
            stick = np.flatnonzero(states == STICK)
            fixed = np.where(states == SLIP, f * p * slide, 0.0)
            m = stick.size
            K = np.zeros((m + 1, m + 1))
            K[:m, :m] = T[np.ix_(stick, stick)]
            K[:m, m] = -1.0
            K[m, :m] = h
            rhs = np.concatenate([s_old[stick] - offset[stick] - T[stick] @ fixed,
                                  [load - h * fixed.sum()]])  # fmt: skip
            sol = np.linalg.solve(K, rhs)
            q = fixed.copy()
            q[stick] = sol[:m]
            d = sol[m]
            ds = offset + T @ q - d - s_old
            new_states, new_slide = states.copy(), slide.copy()
            over = (states == STICK) & (np.abs(q) > f * p)
            new_states[over] = SLIP
            new_slide[over] = np.sign(q[over])
            back = (states == SLIP) & (slide * ds < 0)
            new_states[back] = STICK
            new_slide[back] = 0.0
            if not (over.any() or back.any()):
                return q, d, states, slide
            key = new_states.tobytes() + new_slide.tobytes()
            if key in seen:  # cycling: release one cell at a time
                first = np.flatnonzero(over | back)[0]
                new_states, new_slide = states.copy(), slide.copy()
                new_states[first] = SLIP if over[first] else STICK
                new_slide[first] = np.sign(q[first]) if over[first] else 0.0
            seen.add(key)
            states, slide = new_states, new_slide
        raise RuntimeError(f"the stick/slip active set did not converge ({n} cells)")


def reference_for_scene(scene, *, cells: int = 400) -> dict[str, DissimilarState]:
    """The half-plane reference of a scene, by step name: its P, Q, bulk and increments.

    For scenes whose two faces are Hertzian (cylinder pad on a cylinder or flat specimen),
    loaded by forces (``P``, ``Q``, ``bulk``; not ``delta`` or ``approach``), any materials:
    the answer fretbem's half-plane bodies converge to, and BEM bodies up to their
    finite-body difference. Raises :class:`~fretbem.verification.nowell_hills.NotApplicableError`
    naming the scene key that rules it out.
    """
    curvatures = [scene.pad.shape.curvature, scene.specimen.shape.curvature]
    if any(c is None for c in curvatures) or sum(curvatures) <= 0:
        raise NotApplicableError(
            "[pad] shape / [specimen] shape: the half-plane reference needs a Hertzian gap "
            "(a cylinder pad on a cylinder or flat specimen)"
        )
    load = scene.load
    if load is None or load.delta is not None or load.approach is not None:
        raise NotApplicableError(
            "[load]: the half-plane reference needs force control (P, Q, bulk), not delta or "
            "approach"
        )
    if scene.contact.law != "coulomb":
        raise NotApplicableError(
            f"[contact] law = {scene.contact.law!r}: the half-plane reference is for Coulomb "
            'friction (law = "coulomb")'
        )
    pad, specimen = scene.pad.material, scene.specimen.material
    if pad.plane_stress != specimen.plane_stress:
        raise NotApplicableError(
            "[pad.material] plane / [specimen.material] plane: both bodies must be plane "
            "strain or both plane stress for the half-plane reference"
        )
    model = DissimilarCylinders(
        1.0 / sum(curvatures), pad.E, pad.nu, specimen.E, specimen.nu,
        scene.contact.friction, plane_stress=pad.plane_stress,
    )  # fmt: skip
    history = list(zip(load.P, load.Q, load.bulk, strict=True))
    states = model.solve(history, cells=cells, increments=list(load.increments))
    return dict(zip(load.steps, states, strict=True))
