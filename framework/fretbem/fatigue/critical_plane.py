"""Critical-plane fatigue parameters per point: SWT, Findley, Fatemi-Socie, MWCM, stress and
strain life.

Each parameter is maximised over material planes (3D by default, see :mod:`.planes`): a coarse
grid over the quarter sphere, exact shear amplitudes (minimum circumscribed circle) only where
cheap bounds cannot rule a plane out, then a local pattern search around each point's best
plane with halving steps (in-plane, where there is one angle: a golden-section search of the
best grid plane's bracket, then a parabolic step). Strains come from Hooke's law (isotropic,
linear elastic). The search runs in numpy here or compiled (:mod:`.compiled_search`, numba),
the same algorithm and the same answers to round-off; :func:`use_compiled` picks one by the
search's size.

Names say what they are: ``*_amplitude`` is half the range over the cycle, ``*_max`` the largest
value over the cycle, ``*_mean`` the average of max and min. The shear amplitude is the radius
of the minimum circumscribed circle of the shear-stress path on the plane. ``stress_life``
ranks planes by the mean-stress corrected normal stress amplitude sigma_ar
(:mod:`.mean_stress`), ``strain_life`` by the normal strain amplitude; neither is computed
unless asked for (:data:`DEFAULT_METHODS` are the four critical-plane parameters).
"""

from __future__ import annotations

import functools
import importlib.util
from collections.abc import Sequence

import attrs
import numpy as np

from fretbem.validators import count_field, flag_field, number_field, real_number, shown

from .errors import FatigueInputError
from .mcc import _HALF_SQRT2, circle_bounds_xy, minimum_circumscribed_circle_xy
from .mean_stress import MeanStressCorrection
from .planes import plane_grid, projection

__all__ = [
    "COMPILED_MIN_EVALUATIONS",
    "DEFAULT_METHODS",
    "METHODS",
    "CriterionResult",
    "PlaneSearch",
    "critical_plane_parameters",
    "plane_quantities",
    "search_evaluations",
    "use_compiled",
]

#: the parameter names, in report order
METHODS = ("swt", "findley", "fatemi_socie", "mwcm", "stress_life", "strain_life")
#: the parameters computed when none are named (the stress- and strain-life curves are asked for)
DEFAULT_METHODS = METHODS[:4]

#: relative tolerance for "equal shear amplitude" when MWCM breaks ties by the normal stress
MWCM_TIE_TOLERANCE = 1e-10


def _step(default: float) -> attrs.Converter:
    return number_field(
        "degrees",
        f"give e.g. {default:g}, in (0, 90]",
        low=0.0,
        low_open=True,
        high=90.0,
        error=FatigueInputError,
    )


@attrs.frozen
class PlaneSearch:
    """How the planes are searched.

    Attributes
    ----------
    in_plane_only : bool
        Search only planes containing the out-of-plane axis z (the 2D restriction); the full
        3D search is the default because sigma_zz != 0 in plane strain.
    theta_step_deg, psi_step_deg : float
        Coarse grid steps of the in-plane angle and of the out-of-plane angle. The default
        psi rows, 90 and 45 degrees and the plane normal to z, hold the planes of largest
        normal and shear stress amplitude of a proportional history (z is a principal
        direction of the 2D models' stresses); docs/explanation/fatigue.md measures them.
    refine_levels : int
        Halvings of the step in the local pattern search around each best plane (3D, default
        3); in-plane, ``refine_levels + 1`` golden-section steps in the grid bracket of each
        best plane (default 5).
    chunk_points : int
        Points evaluated at once on the coarse grid (memory ~ steps x chunk x planes).
    compiled : bool or None
        True: the compiled (numba) search (:mod:`.compiled_search`), False: the numpy search;
        None (default) chooses the compiled one for searches large enough to repay loading
        numba (:func:`use_compiled`). Both find the same planes and values to round-off.
    """

    in_plane_only: bool = attrs.field(
        default=False, converter=flag_field("give True or False", error=FatigueInputError)
    )
    theta_step_deg: float = attrs.field(default=5.0, converter=_step(5.0))
    psi_step_deg: float = attrs.field(default=45.0, converter=_step(45.0))
    refine_levels: int = attrs.field(
        default=attrs.Factory(lambda self: 5 if self.in_plane_only else 3, takes_self=True),
        converter=count_field(
            "give e.g. 3 (0: the coarse grid's planes only)", low=0, error=FatigueInputError
        ),
    )
    chunk_points: int = attrs.field(
        default=400, converter=count_field("give e.g. 400", error=FatigueInputError)
    )
    compiled: bool | None = attrs.field(
        default=None, validator=attrs.validators.optional(attrs.validators.instance_of(bool))
    )


@attrs.frozen(eq=False)
class CriterionResult:
    """One parameter at every point, with its critical plane and the stresses on that plane.

    Attributes
    ----------
    method : str
        One of :data:`METHODS`.
    value : ndarray (P,)
        The parameter (SWT in MPa, Findley in MPa, Fatemi-Socie dimensionless, MWCM: the
        shear stress amplitude in MPa, its rho is ``normal_stress_max / shear_stress_amplitude``;
        stress life: the corrected normal stress amplitude sigma_ar in MPa, inf where the mean
        stress reaches the correction's limit; strain life: the normal strain amplitude).
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

    def __init__(
        self,
        name: str,
        *,
        E: float,
        nu: float,
        k: float = 0.0,
        sy: float = 1.0,
        mean_stress: MeanStressCorrection | None = None,
    ):
        self.name = name
        self.needs_shear = name in ("findley", "fatemi_socie", "mwcm")
        self.needs_strain = name in ("swt", "strain_life")
        self.mean_stress = mean_stress or MeanStressCorrection()
        # convex in sin^2 psi at every theta: the 3D maximum is on psi = 0 or 90 degrees
        self.convex_in_tilt = name == "strain_life" or (
            name == "stress_life" and self.mean_stress.name == "none"
        )
        self.G = E / (2.0 * (1.0 + nu))
        self.k = k
        self.sy = sy

    def value(self, q: dict, tau_a: np.ndarray) -> np.ndarray:
        smax = q["normal_stress_max"]
        if self.name == "swt":
            return smax * q["normal_strain_amplitude"]
        if self.name == "strain_life":
            return q["normal_strain_amplitude"]
        if self.name == "stress_life":
            smin = q["normal_stress_min"]
            return self.mean_stress.equivalent_amplitude(0.5 * (smax - smin), 0.5 * (smax + smin))
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


def _make_criteria(methods, E, nu, findley_k, fatemi_socie_k, yield_strength, mean_stress):
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
                mean_stress=mean_stress,
            )
        )
    return criteria


def _coarse_columns(theta, psi, nu, *, strains: bool, shear: bool, in_plane: bool):
    """Float32 coefficients (4, Q G): every linear plane quantity of the grid in one product.

    Quantities, each a linear map of (sxx, syy, sxy, szz) on every grid plane: the normal
    stress, the normal strain times E (Hooke: (1 + nu) sigma_n - nu tr sigma) if ``strains``,
    and the shear path: its one component tau_e in-plane (a straight path), or tau_1, tau_2,
    tau_1 + tau_2 and tau_1 - tau_2 (the extents the circle bounds need) in 3D.
    """
    coef = projection(theta, psi)  # (3, G, 4)
    columns = [coef[0]]
    if strains:
        columns.append((1.0 + nu) * coef[0] - nu * np.array([1.0, 1.0, 0.0, 1.0]))
    if shear and in_plane:
        columns.append(coef[2])
    elif shear:
        columns += [coef[1], coef[2], coef[1] + coef[2], coef[1] - coef[2]]
    return np.concatenate(columns).T.astype(np.float32)


def _coarse(stress, criteria, columns, n_g, E, in_plane, psi=None):
    """Best grid plane per point and criterion: indices into the grid, pruned exact MCC.

    Single precision picks the best grid plane (the refinement is in double): one product
    with ``columns`` (:func:`_coarse_columns`) gives every quantity of every plane, and one
    maximum and one minimum over the steps every summary the criteria and the bounds need.
    In 3D, ``psi`` (G,): the grid's tilts, for the criteria whose maximum is on psi = 0 or
    90 degrees (:func:`_tilt_argbest`).
    """
    n_t, n_p = stress.shape[:2]
    data = (stress.astype(np.float32) @ columns).reshape(n_t, n_p, -1, n_g)
    top, bottom = data.max(axis=0), data.min(axis=0)  # (P, Q, G)
    q = {"normal_stress_max": top[:, 0], "normal_stress_min": bottom[:, 0]}
    best = functools.partial(_tilt_argbest, psi=None if in_plane else psi)
    with_strain = any(c.needs_strain for c in criteria)
    if with_strain:
        q["normal_strain_amplitude"] = 0.5 * (top[:, 1] - bottom[:, 1]) / E
    first = 1 + with_strain  # the first shear quantity
    if not any(c.needs_shear for c in criteria):
        zero = np.zeros((n_p, n_g), dtype=np.float32)
        return {c.name: best(c, c.value(q, zero), c.secondary(q)) for c in criteria}
    span = top[:, first:] - bottom[:, first:]
    if in_plane:  # straight shear path: the amplitude is half its range
        tau = 0.5 * span[:, 0]
        return {c.name: best(c, c.value(q, tau), c.secondary(q)) for c in criteria}
    rx, ry = span[:, 0], span[:, 1]
    ru, rv = span[:, 2] * _HALF_SQRT2, span[:, 3] * _HALF_SQRT2
    tau_lo = 0.5 * np.maximum(np.maximum(rx, ry), np.maximum(ru, rv))
    tau_hi = 0.5 * np.sqrt(np.minimum(rx * rx + ry * ry, ru * ru + rv * rv))
    need = np.zeros((n_p, n_g), dtype=bool)
    for crit in criteria:
        if not crit.needs_shear:
            continue
        lo = crit.value(q, tau_lo)
        hi = crit.value(q, tau_hi)
        lo, hi = np.minimum(lo, hi), np.maximum(lo, hi)
        best_lo = lo.max(axis=1, keepdims=True)
        slack = MWCM_TIE_TOLERANCE * np.abs(best_lo) if crit.name == "mwcm" else 0.0
        need |= hi >= best_lo - slack
    need &= tau_hi > tau_lo * (1.0 + 1e-12)
    tau = tau_lo.copy()
    point, plane = np.nonzero(need)
    if point.size:
        px = data[:, point, first, plane]
        py = data[:, point, first + 1, plane]
        tau[point, plane] = minimum_circumscribed_circle_xy(px, py)[2]
    return {c.name: best(c, c.value(q, tau), c.secondary(q)) for c in criteria}


def _tilt_argbest(crit: _Criterion, values: np.ndarray, secondary, psi) -> np.ndarray:
    """:func:`_argbest` of the grid; in 3D (``psi`` given) a criterion convex in the tilt
    (``convex_in_tilt``) takes its best of the in-plane row and the plane normal to z, where
    its maximum is (docs/explanation/fatigue.md)."""
    if psi is not None and crit.convex_in_tilt:
        tilted = (psi > 0.0) & (psi < 0.5 * np.pi)
        values = np.where(tilted, -np.inf, values)
    return _argbest(crit, values, secondary)


def _plane_stats(
    stress, theta, psi, E, nu, *, shear: bool, strains: bool, in_plane: bool = False, exact=None
) -> dict:
    """Summaries over the cycle on per-point planes ``theta``, ``psi`` (P, G), in double.

    Elementwise products of the stress components with the plane coefficients (no per-point
    matrix products) and reductions over the steps; the shear amplitude is exact where its
    bounds differ (minimum circumscribed circle) and the common bound where they meet (a
    straight shear path). ``in_plane``: every plane contains z (psi = 90 degrees), whose
    shear path is the straight line tau_e: its amplitude is half its range. ``exact``
    (optional): ``exact(smax, tau_lo, tau_hi)`` -> (P, G) mask of the planes whose exact
    amplitude can matter; the others keep the lower bound.
    """
    if in_plane:
        return _in_plane_stats(stress, theta, E, nu, shear=shear, strains=strains)
    c2, s2 = np.cos(2.0 * theta), np.sin(2.0 * theta)
    sp, cp = np.sin(psi), np.cos(psi)
    # sigma_ee = A + B cos 2theta + C sin 2theta, tau_e = C cos 2theta - B sin 2theta
    mean = 0.5 * (stress[:, :, 0, None] + stress[:, :, 1, None])  # (T, P, 1)
    half = 0.5 * (stress[:, :, 0, None] - stress[:, :, 1, None])
    sxy, szz = stress[:, :, 2, None], stress[:, :, 3, None]
    ee = mean + half * c2 + sxy * s2  # (T, P, G)
    sn = (sp * sp) * ee + (cp * cp) * szz
    smax, smin = sn.max(axis=0), sn.min(axis=0)
    out = {"normal_stress_max": smax, "normal_stress_min": smin}
    if strains:
        # normal strain from Hooke's law: eps_n = ((1 + nu) sigma_n - nu tr(sigma)) / E
        en = (1.0 + nu) * sn - nu * (2.0 * mean + szz)
        out["normal_strain_amplitude"] = 0.5 * (en.max(axis=0) - en.min(axis=0)) / E
    if shear:
        n_t, n_p, n_g = sn.shape
        te = sxy * c2 - half * s2
        px = ((sp * cp) * (ee - szz)).reshape(n_t, n_p * n_g)
        py = (sp * te).reshape(n_t, n_p * n_g)
        tau_lo, tau_hi = circle_bounds_xy(px, py)
        tau = tau_lo.copy()
        differ = tau_hi > tau_lo * (1.0 + 1e-12)
        if exact is not None:
            shape = (n_p, n_g)
            differ &= exact(smax, tau_lo.reshape(shape), tau_hi.reshape(shape)).ravel()
        flat = np.flatnonzero(differ)
        if flat.size:
            tau[flat] = minimum_circumscribed_circle_xy(px[:, flat], py[:, flat])[2]
        out["tau"] = tau.reshape(n_p, n_g)
    else:
        out["tau"] = np.zeros_like(smax)
    return out


def _in_plane_stats(stress, theta, E, nu, *, shear: bool, strains: bool) -> dict:
    """:func:`_plane_stats` of planes that contain z: sigma_n = sigma_ee, tau = tau_e."""
    c2, s2 = np.cos(2.0 * theta), np.sin(2.0 * theta)
    mean = 0.5 * (stress[:, :, 0, None] + stress[:, :, 1, None])  # (T, P, 1)
    half = 0.5 * (stress[:, :, 0, None] - stress[:, :, 1, None])
    sxy, szz = stress[:, :, 2, None], stress[:, :, 3, None]
    sn = mean + half * c2 + sxy * s2  # (T, P, G)
    smax, smin = sn.max(axis=0), sn.min(axis=0)
    out = {"normal_stress_max": smax, "normal_stress_min": smin}
    if strains:
        en = (1.0 + nu) * sn - nu * (2.0 * mean + szz)
        out["normal_strain_amplitude"] = 0.5 * (en.max(axis=0) - en.min(axis=0)) / E
    if shear:
        te = sxy * c2 - half * s2
        out["tau"] = 0.5 * (te.max(axis=0) - te.min(axis=0))
    else:
        out["tau"] = np.zeros_like(smax)
    return out


#: (step, point, plane) values per block of points in the per-point plane statistics: the
#: temporaries of a block stay in cache (10,000 points, 4 criteria: 1.7x faster than one block)
STATS_BLOCK = 1 << 15


def _chunked_stats(stress, theta, psi, E, nu, *, exact=None, **flags) -> dict:
    """:func:`_plane_stats` over blocks of points; the same values (elementwise work).

    ``exact(block, smax, tau_lo, tau_hi)``, if given, is asked per block of points.
    """
    n_t, n_p = stress.shape[:2]
    size = max(1, STATS_BLOCK // (n_t * theta.shape[1]))
    blocks = [slice(a, a + size) for a in range(0, n_p, size)]
    parts = [
        _plane_stats(
            stress[:, b],
            theta[b],
            psi[b],
            E,
            nu,
            exact=None if exact is None else functools.partial(exact, b),
            **flags,
        )
        for b in blocks
    ]
    if len(parts) == 1:
        return parts[0]
    return {key: np.concatenate([part[key] for part in parts]) for key in parts[0]}


def _columns(q: dict, cols: slice) -> dict:
    return {key: value[:, cols] for key, value in q.items()}


class _SharedPass:
    """Evaluates the planes of every criterion in one pass: columns per criterion."""

    def __init__(self, stress, criteria, E, nu, in_plane=False):
        self.stress, self.criteria, self.E, self.nu = stress, criteria, E, nu
        self.in_plane = in_plane
        self.shear = any(c.needs_shear for c in criteria)
        self.strains = any(c.needs_strain for c in criteria)

    def __call__(self, theta: np.ndarray, psi: np.ndarray, *, strains: bool = False, against=None):
        """Planes (C, P, G) per criterion -> [(values, secondary, tau, q)] per criterion.

        ``strains`` computes the normal strain amplitude even without SWT (the final planes).
        ``against``: per criterion (values, scale) of the planes these compete with; a plane
        whose value cannot reach them (by its shear amplitude's upper bound) keeps the lower
        bound, which cannot win either, instead of the exact circle. SWT's planes never need
        the circle (the parameter has no shear term).
        """
        n_c, n_p, n_g = theta.shape
        th = theta.transpose(1, 0, 2).reshape(n_p, n_c * n_g)
        ps = psi.transpose(1, 0, 2).reshape(n_p, n_c * n_g)
        q = _chunked_stats(
            self.stress,
            th,
            ps,
            self.E,
            self.nu,
            shear=self.shear,
            strains=self.strains or strains,
            in_plane=self.in_plane,
            exact=functools.partial(self._exact, n_g, against),
        )
        out = []
        for i, crit in enumerate(self.criteria):
            qc = _columns(q, slice(i * n_g, (i + 1) * n_g))
            tau = qc["tau"] if crit.needs_shear else np.zeros_like(qc["tau"])
            out.append((crit.value(qc, tau), crit.secondary(qc), tau, qc))
        return out

    def _exact(self, n_g, against, block, smax, tau_lo, tau_hi) -> np.ndarray:
        """Mask (P, C G) of the planes whose exact shear amplitude can change a decision."""
        need = np.zeros(tau_lo.shape, dtype=bool)
        for i, crit in enumerate(self.criteria):
            cols = slice(i * n_g, (i + 1) * n_g)
            if not crit.needs_shear:
                continue
            if against is None:
                need[:, cols] = True
                continue
            q = {"normal_stress_max": smax[:, cols]}
            top = np.maximum(crit.value(q, tau_lo[:, cols]), crit.value(q, tau_hi[:, cols]))
            value, scale = against[i]
            slack = MWCM_TIE_TOLERANCE * scale[block, None] if crit.name == "mwcm" else 0.0
            need[:, cols] = top >= value[block, None] - slack
        return need


def _refine(evaluate, criteria, theta, psi, steps, levels, in_plane_only):
    """Pattern search: move each point's plane to its best neighbour, halving the steps.

    ``theta``, ``psi`` (C, P): the start plane of every criterion; all criteria's candidate
    planes are evaluated together, one pass per level.
    """
    n_p = theta.shape[1]
    rows = np.arange(n_p)
    start = evaluate(theta[:, :, None], psi[:, :, None])
    values = [v[:, 0] for v, _, _, _ in start]
    second = [None if s is None else s[:, 0] for _, s, _, _ in start]
    scale = [np.maximum(np.abs(v), 1e-300) for v in values]
    for level in range(levels):
        ht, hp = steps[0] / 2 ** (level + 1), steps[1] / 2 ** (level + 1)
        if in_plane_only:
            offsets = np.array([[-ht, 0.0], [ht, 0.0]])
        else:
            offsets = np.array([[-ht, 0.0], [ht, 0.0], [0.0, -hp], [0.0, hp]])
        th = theta[:, :, None] + offsets[:, 0]
        ps = np.clip(psi[:, :, None] + offsets[:, 1], 0.0, np.pi / 2)
        against = list(zip(values, scale, strict=True))
        candidates = evaluate(th, ps, against=against)
        for i, (crit, (v, s, _, _)) in enumerate(zip(criteria, candidates, strict=True)):
            j = _argbest(crit, v, s)
            vj = v[rows, j]
            sj = None if s is None else s[rows, j]
            move = _better(crit, vj, sj, values[i], second[i], scale[i])
            theta[i] = np.where(move, th[i, rows, j], theta[i])
            psi[i] = np.where(move, ps[i, rows, j], psi[i])
            values[i] = np.where(move, vj, values[i])
            if second[i] is not None:
                second[i] = np.where(move, sj, second[i])
    # one parabolic step per angle through the last level's three values
    ht, hp = steps[0] / 2**levels, steps[1] / 2**levels
    offsets = np.array([[-ht, 0.0], [ht, 0.0]] + ([] if in_plane_only else [[0.0, -hp], [0.0, hp]]))
    th = theta[:, :, None] + offsets[:, 0]
    ps = np.clip(psi[:, :, None] + offsets[:, 1], 0.0, np.pi / 2)
    new_theta, new_psi = theta.copy(), psi.copy()
    pairs = [((0, 1), ht), ((2, 3), hp)][: 1 if in_plane_only else 2]
    for i, (v, _, _, _) in enumerate(evaluate(th, ps)):
        shift = []
        for (lo, hi), h in pairs:
            # inf - inf (a static failure of stress_life) is nan: no step
            with np.errstate(divide="ignore", invalid="ignore"):
                curv = v[:, lo] - 2.0 * values[i] + v[:, hi]
                d = np.where(curv < 0, 0.5 * h * (v[:, lo] - v[:, hi]) / curv, 0.0)
            shift.append(np.clip(np.nan_to_num(d), -h, h))
        new_theta[i] = theta[i] + shift[0]
        if not in_plane_only:
            new_psi[i] = np.clip(psi[i] + shift[1], 0.0, np.pi / 2)
    against = list(zip(values, scale, strict=True))
    final = evaluate(new_theta[:, :, None], new_psi[:, :, None], against=against)
    for i, (crit, (v, s2, _, _)) in enumerate(zip(criteria, final, strict=True)):
        move = _better(
            crit, v[:, 0], None if s2 is None else s2[:, 0], values[i], second[i], scale[i]
        )
        theta[i] = np.where(move, new_theta[i], theta[i])
        psi[i] = np.where(move, new_psi[i], psi[i])
    return np.mod(theta, np.pi), psi


#: the golden section: the new point's share of the larger side of the bracket
GOLDEN = 0.3819660112501051


def _golden(evaluate, criteria, theta, step, levels):
    """In-plane refinement: golden-section search of each point's grid bracket, then a
    parabolic step.

    ``theta`` (C, P): every criterion's best grid plane; its bracket is the grid's two
    neighbours (``step`` either side). Each of ``levels + 1`` iterations evaluates one plane
    per criterion and point, in the larger side of the bracket at the golden ratio, and the
    bracket closes on the better of it and the current plane; then the vertex of the parabola
    through the bracket's ends and its best plane is tried. All criteria share each pass.
    """
    n_c, n_p = theta.shape
    psi = np.full((n_c, n_p, 1), np.pi / 2)
    start = evaluate(theta[:, :, None], psi)
    value = [v[:, 0] for v, _, _, _ in start]
    second = [None if s is None else s[:, 0] for _, s, _, _ in start]
    scale = [np.maximum(np.abs(v), 1e-300) for v in value]
    lo, hi = np.full_like(theta, -step), np.full_like(theta, step)  # from the current plane
    ends = evaluate(np.stack([theta - step, theta + step], axis=-1), np.concatenate([psi, psi], -1))
    f_lo = np.stack([v[:, 0] for v, _, _, _ in ends])
    f_hi = np.stack([v[:, 1] for v, _, _, _ in ends])
    for _ in range(levels + 1):
        right = hi > -lo
        x = np.where(right, GOLDEN * hi, GOLDEN * lo)
        found = evaluate((theta + x)[:, :, None], psi)
        for i, (crit, (v, s, _, _)) in enumerate(zip(criteria, found, strict=True)):
            v, s = v[:, 0], None if s is None else s[:, 0]
            up = _better(crit, v, s, value[i], second[i], scale[i])
            r = right[i]
            # better: the bracket closes around the new plane; else the new plane is an end
            lo[i], hi[i], f_lo[i], f_hi[i] = (
                np.where(up, np.where(r, -x[i], lo[i] - x[i]), np.where(r, lo[i], x[i])),
                np.where(up, np.where(r, hi[i] - x[i], -x[i]), np.where(r, x[i], hi[i])),
                np.where(up & r, value[i], np.where(~up & ~r, v, f_lo[i])),
                np.where(up & ~r, value[i], np.where(~up & r, v, f_hi[i])),
            )
            theta[i] = np.where(up, theta[i] + x[i], theta[i])
            value[i] = np.where(up, v, value[i])
            if second[i] is not None:
                second[i] = np.where(up, s, second[i])
    # the vertex of the parabola through (lo, f_lo), (0, value), (hi, f_hi), inside the bracket
    centre = np.stack(value)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        a, b = centre - f_hi, centre - f_lo
        x = -0.5 * (lo * lo * a - hi * hi * b) / (-lo * a + hi * b)
    x = np.where(np.isfinite(x) & (x > lo) & (x < hi), x, 0.0)
    found = evaluate((theta + x)[:, :, None], psi)
    for i, (crit, (v, s, _, _)) in enumerate(zip(criteria, found, strict=True)):
        s = None if s is None else s[:, 0]
        up = _better(crit, v[:, 0], s, value[i], second[i], scale[i])
        theta[i] = np.where(up, theta[i] + x[i], theta[i])
    return np.mod(theta, np.pi)


#: (step, point, plane) evaluations from which the compiled search is the default: about
#: what loading numba (0.45 s) and the cached kernel (0.06 s) cost at the numpy search's
#: 1e-8 s per evaluation (0.38 s for 10,000 points, 9 steps, 73 grid + 240 refinement planes
#: in 3D, where a fresh process's compiled search takes 0.39 s; 0.11 s for 36 + 120
#: in-plane); benchmarks/fatigue_grid.py
COMPILED_MIN_EVALUATIONS = 5e7


def search_evaluations(search: PlaneSearch, n_steps: int, n_points: int, n_criteria: int) -> float:
    """(step, point, plane) evaluations of a search: the grid and the refinement (about 15
    planes per criterion and candidate direction)."""
    theta, _ = plane_grid(
        in_plane_only=search.in_plane_only,
        theta_step_deg=search.theta_step_deg,
        psi_step_deg=search.psi_step_deg,
    )
    refine = 15 * n_criteria * (2 if search.in_plane_only else 4)
    return float(n_steps) * n_points * (theta.size + refine)


def use_compiled(search: PlaneSearch, n_steps: int, n_points: int, n_criteria: int) -> bool:
    """Whether a search runs compiled: as ``search.compiled`` says, or (None) where numba is
    installed and the search has at least :data:`COMPILED_MIN_EVALUATIONS` evaluations.

    The choice depends on the search alone, not on what the process ran before, so the same
    search gives the same bits every time (the two paths agree to round-off, not to the bit).
    """
    installed = importlib.util.find_spec("numba") is not None
    if search.compiled is True and not installed:
        raise FatigueInputError(
            "PlaneSearch(compiled=True) needs numba, which is not installed: pip install "
            "numba, or leave compiled=None to use it only where it is available"
        )
    if search.compiled is not None:
        return search.compiled
    evaluations = search_evaluations(search, n_steps, n_points, n_criteria)
    return installed and evaluations >= COMPILED_MIN_EVALUATIONS


def _compiled_parameters(stress, criteria, search, theta_g, psi_g, E, nu) -> dict:
    """:func:`critical_plane_parameters` by the compiled search (:mod:`.compiled_search`)."""
    from . import compiled_search as compiled  # numba: loaded only when chosen

    codes = np.array([METHODS.index(c.name) for c in criteria], dtype=np.int64)
    kinds = {"none": compiled.NO_CORRECTION, "gerber": compiled.GERBER}
    par = np.array(
        [
            [
                c.k,
                c.sy,
                c.G,
                kinds.get(c.mean_stress.name, compiled.LINEAR),
                c.mean_stress.limit or 1.0,
            ]
            for c in criteria
        ]
    )
    thetas = theta_g if search.in_plane_only else np.unique(theta_g[:-1])
    psis = psi_g[: max(1, (theta_g.size - 1) // thetas.size)]
    order = np.arange(theta_g.size)
    if not search.in_plane_only:  # row by row of psi (plane_grid goes theta by theta)
        rows = np.arange(psis.size)[:, None] + psis.size * np.arange(thetas.size)[None, :]
        order = np.append(rows.ravel(), theta_g.size - 1)
        theta_g, psi_g = theta_g[order], psi_g[order]
    grid = np.stack([np.cos(2 * theta_g), np.sin(2 * theta_g), np.sin(psi_g), np.cos(psi_g)])
    axes = (np.cos(2 * thetas), np.sin(2 * thetas), np.sin(psis), np.cos(psis))
    steps = np.deg2rad([search.theta_step_deg, search.psi_step_deg])
    theta, psi, res = compiled.search(
        np.ascontiguousarray(stress),
        grid,
        axes,
        order,
        theta_g,
        psi_g,
        codes,
        par,
        float(nu),
        float(E),
        steps,
        int(search.refine_levels),
        bool(search.in_plane_only),
    )
    # tau: for a criterion whose search needs no shear, its plane's own (for the report)
    rows = compiled.report(theta, psi, res, E / (2.0 * (1.0 + nu)))
    names = compiled.REPORT_ROWS
    return {
        crit.name: CriterionResult(crit.name, **dict(zip(names, rows[:, i], strict=True)))
        for i, crit in enumerate(criteria)
    }


def _plane_shear_amplitude(stress, theta, psi, E, nu) -> np.ndarray:
    """The shear amplitude on each point's plane (theta, psi): what a criterion whose search
    needs no shear (SWT, stress_life, strain_life) reports of its critical plane."""
    planes = projection(theta, psi)[:, :, None]  # (3, P, 1, 4): one plane per point
    path = plane_quantities(stress, planes, E, nu, strains=False)
    return minimum_circumscribed_circle_xy(path["path_x"], path["path_y"])[2]


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
    methods: Sequence[str] = DEFAULT_METHODS,
    findley_k: float | None = None,
    fatemi_socie_k: float | None = None,
    yield_strength: float | None = None,
    mean_stress: MeanStressCorrection | None = None,
    search: PlaneSearch | None = None,
) -> dict[str, CriterionResult]:
    """Each requested critical-plane parameter at every point of a stress cycle.

    ``stress`` (n_steps, n_points, 4): [sxx, syy, sxy, szz] in MPa over ONE cycle (select it
    with :func:`fretbem.fatigue.cycle.select_cycle`). ``E``, ``nu``: elastic constants for the
    strains. ``mean_stress``: the correction of ``stress_life`` (none by default). Returns
    ``{method: CriterionResult}``.
    """
    stress = _validate_stress(stress)
    E, nu = (
        real_number(name, value, what=what, fix=f"give {name}", error=FatigueInputError)
        for name, value, what in (("E", E, "MPa"), ("nu", nu, "Poisson's ratio"))
    )
    findley_k, fatemi_socie_k, yield_strength = (
        None
        if value is None
        else real_number(
            name, value, what=what, fix=f"give {name}, or None", error=FatigueInputError
        )
        for name, value, what in (
            ("findley_k", findley_k, "the Findley normal-stress factor"),
            ("fatemi_socie_k", fatemi_socie_k, "the Fatemi-Socie factor"),
            ("yield_strength", yield_strength, "MPa"),
        )
    )
    if isinstance(methods, str):
        raise FatigueInputError(
            f"methods must be a list of method names, got the string {methods!r}; give "
            f"[{methods!r}]"
        )
    if search is not None and not isinstance(search, PlaneSearch):
        raise FatigueInputError(f"search must be a PlaneSearch or None, got {shown(search)}")
    if not (E > 0 and -1.0 < nu < 0.5):
        raise FatigueInputError(
            f"elastic constants must have E > 0 and -1 < nu < 0.5, got {E}, {nu}"
        )
    search = search or PlaneSearch()
    criteria = _make_criteria(
        methods, E, nu, findley_k, fatemi_socie_k, yield_strength, mean_stress
    )
    theta_g, psi_g = plane_grid(
        in_plane_only=search.in_plane_only,
        theta_step_deg=search.theta_step_deg,
        psi_step_deg=search.psi_step_deg,
    )
    if use_compiled(search, stress.shape[0], stress.shape[1], len(criteria)):
        return _compiled_parameters(stress, criteria, search, theta_g, psi_g, E, nu)
    n_points = stress.shape[1]
    best = {c.name: np.empty(n_points, dtype=int) for c in criteria}
    # every criterion convex in the tilt: only the in-plane row and psi = 0 are candidates
    grid = np.arange(theta_g.size)
    if not search.in_plane_only and all(c.convex_in_tilt for c in criteria):
        grid = np.flatnonzero((psi_g == 0.5 * np.pi) | (psi_g == 0.0))
    columns = _coarse_columns(
        theta_g[grid],
        psi_g[grid],
        nu,
        strains=any(c.needs_strain for c in criteria),
        shear=any(c.needs_shear for c in criteria),
        in_plane=search.in_plane_only,
    )
    for start in range(0, n_points, search.chunk_points):
        part = slice(start, start + search.chunk_points)
        chunk_best = _coarse(
            stress[:, part], criteria, columns, grid.size, E, search.in_plane_only, psi_g[grid]
        )
        for name, idx in chunk_best.items():
            best[name][part] = grid[idx]
    steps = (np.deg2rad(search.theta_step_deg), np.deg2rad(search.psi_step_deg))
    evaluate = _SharedPass(stress, criteria, E, nu, in_plane=search.in_plane_only)
    theta = np.stack([theta_g[best[c.name]] for c in criteria])
    psi = np.stack([psi_g[best[c.name]] for c in criteria])
    if search.in_plane_only:
        theta = _golden(evaluate, criteria, theta, steps[0], search.refine_levels)
    else:
        theta, psi = _refine(evaluate, criteria, theta, psi, steps, search.refine_levels, False)
    final = evaluate(theta[:, :, None], psi[:, :, None], strains=True)
    G = E / (2.0 * (1.0 + nu))
    results = {}
    for i, (crit, (values, _, tau, q)) in enumerate(zip(criteria, final, strict=True)):
        smax, smin = q["normal_stress_max"][:, 0], q["normal_stress_min"][:, 0]
        strain = q["normal_strain_amplitude"]
        if not crit.needs_shear:  # its search needs no shear: the plane's own, for the report
            tau = _plane_shear_amplitude(stress, theta[i], psi[i], E, nu)[:, None]
        results[crit.name] = CriterionResult(
            method=crit.name,
            value=values[:, 0],
            normal_angle_deg=np.rad2deg(theta[i]),
            normal_tilt_deg=90.0 - np.rad2deg(psi[i]),
            shear_stress_amplitude=tau[:, 0],
            normal_stress_max=smax,
            normal_stress_amplitude=0.5 * (smax - smin),
            normal_stress_mean=0.5 * (smax + smin),
            normal_strain_amplitude=strain[:, 0],
            shear_strain_amplitude=tau[:, 0] / G,
        )
    return results
