"""Critical-plane fatigue parameters per point: Smith-Watson-Topper, Findley, Fatemi-Socie, MWCM.

Each parameter is maximised over material planes (3D by default, see :mod:`.planes`): a coarse
grid over the quarter sphere, exact shear amplitudes (minimum circumscribed circle) only where
cheap bounds cannot rule a plane out, then a local pattern search around each point's best
plane with halving steps. Strains come from Hooke's law (isotropic, linear elastic).

Names say what they are: ``*_amplitude`` is half the range over the cycle, ``*_max`` the largest
value over the cycle, ``*_mean`` the average of max and min. The shear amplitude is the radius
of the minimum circumscribed circle of the shear-stress path on the plane.
"""

from __future__ import annotations

from collections.abc import Sequence

import attrs
import numpy as np

from .errors import FatigueInputError
from .mcc import circle_bounds_xy, minimum_circumscribed_circle_xy
from .planes import plane_grid, projection

__all__ = [
    "METHODS",
    "CriterionResult",
    "PlaneSearch",
    "critical_plane_parameters",
    "plane_quantities",
]

#: the parameter names, in report order
METHODS = ("swt", "findley", "fatemi_socie", "mwcm")

#: relative tolerance for "equal shear amplitude" when MWCM breaks ties by the normal stress
MWCM_TIE_TOLERANCE = 1e-10


@attrs.frozen
class PlaneSearch:
    """How the planes are searched.

    Attributes
    ----------
    in_plane_only : bool
        Search only planes containing the out-of-plane axis z (the 2D restriction); the full
        3D search is the default because sigma_zz != 0 in plane strain.
    theta_step_deg, psi_step_deg : float
        Coarse grid steps of the in-plane angle and of the out-of-plane angle.
    refine_levels : int
        Halvings of the step in the local pattern search around each best plane.
    chunk_points : int
        Points evaluated at once on the coarse grid (memory ~ steps x chunk x planes).
    """

    in_plane_only: bool = False
    theta_step_deg: float = 5.0
    psi_step_deg: float = 10.0
    refine_levels: int = 5
    chunk_points: int = 400


@attrs.frozen(eq=False)
class CriterionResult:
    """One parameter at every point, with its critical plane and the stresses on that plane.

    Attributes
    ----------
    method : str
        One of :data:`METHODS`.
    value : ndarray (P,)
        The parameter (SWT in MPa, Findley in MPa, Fatemi-Socie dimensionless, MWCM: the
        shear stress amplitude in MPa; its rho is ``normal_stress_max / shear_stress_amplitude``).
    normal_angle_deg : ndarray (P,)
        In-plane angle of the plane normal's projection, from x towards y, in [0, 180).
    normal_tilt_deg : ndarray (P,)
        Angle between the normal and the x-y plane (0: the plane contains z).
    shear_stress_amplitude, normal_stress_max, normal_stress_amplitude, normal_stress_mean,
    normal_strain_amplitude, shear_strain_amplitude : ndarray (P,)
        Stresses (MPa) and strains on the critical plane over the cycle.
    """

    method: str
    value: np.ndarray
    normal_angle_deg: np.ndarray
    normal_tilt_deg: np.ndarray
    shear_stress_amplitude: np.ndarray
    normal_stress_max: np.ndarray
    normal_stress_amplitude: np.ndarray
    normal_stress_mean: np.ndarray
    normal_strain_amplitude: np.ndarray
    shear_strain_amplitude: np.ndarray

    @property
    def normal(self) -> np.ndarray:
        """Unit normals (P, 3) of the critical planes."""
        th = np.deg2rad(self.normal_angle_deg)
        psi = np.deg2rad(90.0 - self.normal_tilt_deg)
        return np.stack([np.sin(psi) * np.cos(th), np.sin(psi) * np.sin(th), np.cos(psi)], -1)

    @property
    def rho(self) -> np.ndarray:
        """sigma_n,max / tau_a on the critical plane (the MWCM stress ratio); inf if tau_a = 0."""
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(
                self.shear_stress_amplitude > 0,
                self.normal_stress_max / self.shear_stress_amplitude,
                np.inf,
            )


def plane_quantities(
    stress: np.ndarray, coef: np.ndarray, E: float, nu: float, *, strains: bool = True
) -> dict:
    """Normal stress/strain summaries and shear paths of (T, P, 4) stress on planes ``coef``.

    ``coef`` (3, G, 4) for the same planes at every point, or (3, P, G, 4) per point.
    Returns summaries over (P, G) and the shear path components (T, P*G) each; the normal
    strain amplitude only if ``strains``.
    """
    if coef.ndim == 3:
        sn, t1, t2 = (stress @ c.T for c in coef)  # (T, P, G)
    else:
        per_point = stress.transpose(1, 0, 2)  # (P, T, 4) @ (P, 4, G) -> (P, T, G)
        sn, t1, t2 = (np.matmul(per_point, c.transpose(0, 2, 1)).transpose(1, 0, 2) for c in coef)
    n_t, n_p, n_g = sn.shape
    out = {
        "normal_stress_max": sn.max(axis=0),
        "normal_stress_min": sn.min(axis=0),
        "path_x": t1.reshape(n_t, n_p * n_g),
        "path_y": t2.reshape(n_t, n_p * n_g),
    }
    if strains:
        # normal strain from Hooke's law: eps_n = ((1 + nu) sigma_n - nu tr(sigma)) / E
        trace = stress[..., 0] + stress[..., 1] + stress[..., 3]  # (T, P)
        en = (1.0 + nu) * sn - nu * trace[:, :, None]
        out["normal_strain_amplitude"] = 0.5 * (en.max(axis=0) - en.min(axis=0)) / E
    return out


class _Criterion:
    """A parameter as a function of the plane quantities; bounds for pruning from tau_a bounds."""

    def __init__(self, name: str, *, E: float, nu: float, k: float = 0.0, sy: float = 1.0):
        self.name = name
        self.needs_shear = name != "swt"
        self.G = E / (2.0 * (1.0 + nu))
        self.k = k
        self.sy = sy

    def value(self, q: dict, tau_a: np.ndarray) -> np.ndarray:
        smax = q["normal_stress_max"]
        if self.name == "swt":
            return smax * q["normal_strain_amplitude"]
        if self.name == "findley":
            return tau_a + self.k * smax
        if self.name == "fatemi_socie":
            return (tau_a / self.G) * (1.0 + self.k * smax / self.sy)
        return tau_a  # mwcm: the plane of largest shear amplitude

    def secondary(self, q: dict) -> np.ndarray | None:
        return q["normal_stress_max"] if self.name == "mwcm" else None


def _better(crit: _Criterion, new, new2, old, old2, scale) -> np.ndarray:
    if crit.name != "mwcm":
        return new > old
    tol = MWCM_TIE_TOLERANCE * scale
    return (new > old + tol) | ((new >= old - tol) & (new2 > old2))


def _argbest(crit: _Criterion, values: np.ndarray, secondary) -> np.ndarray:
    """Index of the best plane per row of ``values`` (P, G)."""
    if crit.name != "mwcm":
        return np.argmax(values, axis=1)
    top = values.max(axis=1, keepdims=True)
    tol = MWCM_TIE_TOLERANCE * np.maximum(np.abs(top), 1e-300)
    tied = values >= top - tol
    return np.argmax(np.where(tied, secondary, -np.inf), axis=1)


def _make_criteria(methods, E, nu, findley_k, fatemi_socie_k, yield_strength):
    criteria = []
    for name in methods:
        if name not in METHODS:
            raise FatigueInputError(f"unknown fatigue method {name!r}; choose from {METHODS}")
        if name == "findley" and findley_k is None:
            raise FatigueInputError(
                "the Findley parameter needs its normal-stress factor k: give findley_k "
                "(or a material with torsion and bending fatigue limits)"
            )
        if name == "fatemi_socie" and (fatemi_socie_k is None or yield_strength is None):
            raise FatigueInputError(
                "the Fatemi-Socie parameter needs fatemi_socie_k and the yield strength "
                "(material yield_strength)"
            )
        criteria.append(
            _Criterion(
                name,
                E=E,
                nu=nu,
                k={"findley": findley_k, "fatemi_socie": fatemi_socie_k}.get(name) or 0.0,
                sy=yield_strength or 1.0,
            )
        )
    return criteria


def _coarse(stress, criteria, theta, psi, E, nu):
    """Best grid plane per point and criterion: (theta, psi) indices, pruned exact MCC."""
    # single precision is enough to pick the best grid plane; the refinement is in double
    coef = projection(theta, psi).astype(np.float32)
    with_swt = any(c.name == "swt" for c in criteria)
    q = plane_quantities(stress.astype(np.float32), coef, E, nu, strains=with_swt)
    n_p, n_g = q["normal_stress_max"].shape
    px, py = q["path_x"], q["path_y"]
    if not any(c.needs_shear and c.name != "swt" for c in criteria):
        zero = np.zeros((n_p, n_g))
        return {c.name: _argbest(c, c.value(q, zero), c.secondary(q)) for c in criteria}
    tau_lo, tau_hi = (b.reshape(n_p, n_g) for b in circle_bounds_xy(px, py))
    need = np.zeros((n_p, n_g), dtype=bool)
    for crit in criteria:
        if crit.name == "swt":
            continue
        lo = crit.value(q, tau_lo)
        hi = crit.value(q, tau_hi)
        lo, hi = np.minimum(lo, hi), np.maximum(lo, hi)
        best_lo = lo.max(axis=1, keepdims=True)
        slack = MWCM_TIE_TOLERANCE * np.abs(best_lo) if crit.name == "mwcm" else 0.0
        need |= hi >= best_lo - slack
    need &= tau_hi > tau_lo * (1.0 + 1e-12)
    tau = tau_lo.copy()
    flat = np.flatnonzero(need.ravel())
    if flat.size:
        _, _, radius = minimum_circumscribed_circle_xy(px[:, flat], py[:, flat])
        tau.ravel()[flat] = radius
    best = {}
    for crit in criteria:
        values = crit.value(q, tau)
        idx = _argbest(crit, values, crit.secondary(q))
        best[crit.name] = idx
    return best


def _evaluate(stress, crit, theta, psi, E, nu):
    """Quantities on per-point planes theta, psi (P, G): values, secondary, tau_a, q."""
    coef = projection(theta, psi)  # (3, P, G, 4)
    q = plane_quantities(stress, coef, E, nu)
    n_p, n_g = theta.shape
    if crit.needs_shear:
        _, _, tau = minimum_circumscribed_circle_xy(q["path_x"], q["path_y"])
        tau = tau.reshape(n_p, n_g)
    else:
        tau = np.zeros((n_p, n_g))
    return crit.value(q, tau), crit.secondary(q), tau, q


def _refine(stress, crit, theta, psi, steps, levels, in_plane_only, E, nu):
    """Pattern search: move each point's plane to its best neighbour, halving the steps."""
    values, second, _, _ = _evaluate(stress, crit, theta[:, None], psi[:, None], E, nu)
    values, second = values[:, 0], None if second is None else second[:, 0]
    scale = np.maximum(np.abs(values), 1e-300)
    for level in range(levels):
        ht, hp = steps[0] / 2 ** (level + 1), steps[1] / 2 ** (level + 1)
        if in_plane_only:
            offsets = np.array([[-ht, 0.0], [ht, 0.0]])
        else:
            offsets = np.array([[-ht, 0.0], [ht, 0.0], [0.0, -hp], [0.0, hp]])
        th = theta[:, None] + offsets[None, :, 0]
        ps = np.clip(psi[:, None] + offsets[None, :, 1], 0.0, np.pi / 2)
        v, s, _, _ = _evaluate(stress, crit, th, ps, E, nu)
        j = _argbest(crit, v, s)
        rows = np.arange(theta.size)
        vj = v[rows, j]
        sj = None if s is None else s[rows, j]
        move = _better(crit, vj, sj, values, second, scale)
        theta = np.where(move, th[rows, j], theta)
        psi = np.where(move, ps[rows, j], psi)
        values = np.where(move, vj, values)
        if second is not None:
            second = np.where(move, sj, second)
    # one parabolic step per angle through the last level's three values
    ht, hp = steps[0] / 2**levels, steps[1] / 2**levels
    offsets = np.array([[-ht, 0.0], [ht, 0.0]] + ([] if in_plane_only else [[0.0, -hp], [0.0, hp]]))
    th = theta[:, None] + offsets[None, :, 0]
    ps = np.clip(psi[:, None] + offsets[None, :, 1], 0.0, np.pi / 2)
    v, _, _, _ = _evaluate(stress, crit, th, ps, E, nu)
    shift = []
    pairs = [((0, 1), ht), ((2, 3), hp)][: 1 if in_plane_only else 2]
    for (lo, hi), h in pairs:
        curv = v[:, lo] - 2.0 * values + v[:, hi]
        with np.errstate(divide="ignore", invalid="ignore"):
            d = np.where(curv < 0, 0.5 * h * (v[:, lo] - v[:, hi]) / curv, 0.0)
        shift.append(np.clip(np.nan_to_num(d), -h, h))
    new_theta = theta + shift[0]
    new_psi = psi if in_plane_only else np.clip(psi + shift[1], 0.0, np.pi / 2)
    v, s2, _, _ = _evaluate(stress, crit, new_theta[:, None], new_psi[:, None], E, nu)
    move = _better(crit, v[:, 0], None if s2 is None else s2[:, 0], values, second, scale)
    theta = np.where(move, new_theta, theta)
    psi = np.where(move, new_psi, psi)
    return np.mod(theta, np.pi), psi


def _validate_stress(stress) -> np.ndarray:
    arr = np.asarray(stress, dtype=float)
    if arr.ndim != 3 or arr.shape[2] != 4 or arr.shape[0] < 2 or arr.shape[1] < 1:
        raise FatigueInputError(
            "the stress history must have shape (n_steps >= 2, n_points, 4) with components "
            f"[sxx, syy, sxy, szz] in MPa, got {arr.shape}"
        )
    if not np.all(np.isfinite(arr)):
        raise FatigueInputError("the stress history contains NaN or infinite values")
    return arr


def critical_plane_parameters(
    stress: np.ndarray,
    *,
    E: float,
    nu: float,
    methods: Sequence[str] = METHODS,
    findley_k: float | None = None,
    fatemi_socie_k: float | None = None,
    yield_strength: float | None = None,
    search: PlaneSearch | None = None,
) -> dict[str, CriterionResult]:
    """Each requested critical-plane parameter at every point of a stress cycle.

    ``stress`` (n_steps, n_points, 4): [sxx, syy, sxy, szz] in MPa over ONE cycle (select it
    with :func:`fretbem.fatigue.cycle.select_cycle`). ``E``, ``nu``: elastic constants for the
    strains. Returns ``{method: CriterionResult}``.
    """
    stress = _validate_stress(stress)
    if not (E > 0 and -1.0 < nu < 0.5):
        raise FatigueInputError(
            f"elastic constants must have E > 0 and -1 < nu < 0.5, got {E}, {nu}"
        )
    search = search or PlaneSearch()
    criteria = _make_criteria(methods, E, nu, findley_k, fatemi_socie_k, yield_strength)
    theta_g, psi_g = plane_grid(
        in_plane_only=search.in_plane_only,
        theta_step_deg=search.theta_step_deg,
        psi_step_deg=search.psi_step_deg,
    )
    n_points = stress.shape[1]
    best = {c.name: np.empty(n_points, dtype=int) for c in criteria}
    for start in range(0, n_points, search.chunk_points):
        part = slice(start, start + search.chunk_points)
        chunk_best = _coarse(stress[:, part], criteria, theta_g, psi_g, E, nu)
        for name, idx in chunk_best.items():
            best[name][part] = idx
    steps = (np.deg2rad(search.theta_step_deg), np.deg2rad(search.psi_step_deg))
    results = {}
    for crit in criteria:
        theta = theta_g[best[crit.name]]
        psi = psi_g[best[crit.name]]
        theta, psi = _refine(
            stress, crit, theta, psi, steps, search.refine_levels, search.in_plane_only, E, nu
        )
        values, _, tau, q = _evaluate(stress, crit, theta[:, None], psi[:, None], E, nu)
        smax, smin = q["normal_stress_max"][:, 0], q["normal_stress_min"][:, 0]
        G = E / (2.0 * (1.0 + nu))
        results[crit.name] = CriterionResult(
            method=crit.name,
            value=values[:, 0],
            normal_angle_deg=np.rad2deg(theta),
            normal_tilt_deg=90.0 - np.rad2deg(psi),
            shear_stress_amplitude=tau[:, 0],
            normal_stress_max=smax,
            normal_stress_amplitude=0.5 * (smax - smin),
            normal_stress_mean=0.5 * (smax + smin),
            normal_strain_amplitude=q["normal_strain_amplitude"][:, 0],
            shear_strain_amplitude=tau[:, 0] / G,
        )
    return results
