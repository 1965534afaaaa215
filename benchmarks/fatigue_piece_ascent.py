"""A study: the in-plane critical-plane refinement as an exact ascent over the criterion's pieces.

Not the search the framework runs (:mod:`fretbem.fatigue.critical_plane`, in-plane: a
golden-section search of each best grid plane's bracket and a parabolic step, 7 evaluations of
every step per criterion and point compiled, 9 in numpy; before it a pattern search of five
halving levels, 13): a prototype of another refinement, kept with its measurements (issue 28
item 1).

On a plane that contains z, at angle theta, each step's normal stress, E times normal strain
and shear stress are sinusoids in phi = 2 theta; a criterion is a function of their extremes
over the steps. Where the steps that attain those extremes stay the same (a piece) the
criterion is a closed form in phi, with closed-form derivatives. Every parameter grows with
the maxima and falls with the minima it uses where it is positive (Findley and Fatemi-Socie
with k >= 0, SWT at tensile planes, stress life below its limit), so it is locally the maximum
of smooth pieces and its local maxima are smooth maxima of one piece. The ascent: the grid
plane and two probes half a grid step either side (the pattern search's first level: two
maxima within a grid cell, across a kink, are common), then from the best of the three a
safeguarded Newton step to the maximum of its piece (no pass over the steps), an evaluation
there, and again until the steps stay the same (exact: a local maximum) or five passes are
spent; a move is kept only if the evaluated value is better.

Measured against the pattern search (``--points 30``, load ~11; the script now compares with
the framework's search, whichever it is): against the 0.01-degree scan of
``benchmarks/fatigue_accuracy.py`` the same worst shortfalls on every criterion but SWT at
compressive planes (5.7e-2 -> 6.7e-2 of the largest value: a kink maximum, the parameter
falls as the strain range grows; the pattern search misses it too); 4.1 evaluations per
criterion and point instead of 13. But each evaluation must also find the steps of the
extremes (selects that the compiled loops do not vectorise: ~140 ns per point against ~50 ns
for a vectorised summary, in one process) and the Newton steps cost about as much again, so
the ascent was slower: numpy 190 against 120 ms on the workflows benchmark's 10,000 points,
and a compiled version (numba, written for this study and not kept) 41-46 against 25 ms in
one process. Kept for the next attempt: the evaluation count is the lead, the cost per
evaluation is what to beat.

Run from the repository root::

    OPENBLAS_NUM_THREADS=1 python benchmarks/fatigue_piece_ascent.py --points 30
"""

from __future__ import annotations

import argparse
import functools
import time

import fatigue_accuracy as fa
import fatigue_phases as fph
import numpy as np

from fretbem.fatigue import METHODS, PlaneSearch, critical_plane_parameters
from fretbem.fatigue import critical_plane as cp
from fretbem.testing.fatigue import in_plane_scan

#: Newton (or bisection) steps on one piece; the step in 2 theta below which it stops (rad)
NEWTON_STEPS = 8
ASCENT_TOLERANCE = 1e-12
#: the two probes' distance from the grid plane, in grid steps
PROBE = 0.5
#: evaluations of every step (per criterion and point), ascents started
EVALUATIONS = [0, 0]

#: the extremes each criterion's value uses: 0, 1 sigma_n max, min; 2, 3 E eps_n max, min;
#: 4, 5 tau max, min (a change of another one's step does not change the piece)
_USES = {
    "swt": (0, 2, 3),
    "strain_life": (2, 3),
    "stress_life": (0, 1),
    "findley": (0, 4, 5),
    "fatemi_socie": (0, 4, 5),
    "mwcm": (4, 5),
}


def piece_uses(name: str) -> tuple[int, ...]:
    """Indices of the extremes (see :func:`line_extremes`) criterion ``name`` depends on."""
    return _USES[name]


def _parts(stress, nu):
    """(mean, half difference, sxy, trace) of every (step, point): the sinusoids' terms."""
    mean = 0.5 * (stress[:, :, 0] + stress[:, :, 1])
    half = 0.5 * (stress[:, :, 0] - stress[:, :, 1])
    return mean, half, stress[:, :, 2], 2.0 * mean + stress[:, :, 3]


def line_extremes(parts, c, s, nu):
    """Extremes (6, P) over the steps of sigma_n, E eps_n, tau on the planes (cos, sin) 2theta
    ``c``, ``s`` (P,), and their steps (6, P) (the first at ties): max and min of each."""
    mean, half, sxy, trace = parts
    sn = mean + half * c + sxy * s
    en = (1.0 + nu) * sn - nu * trace
    te = sxy * c - half * s
    cols = np.arange(c.size)
    ext, idx = [], []
    for q in (sn, en, te):
        for pick in (np.argmax, np.argmin):
            i = pick(q, axis=0)
            idx.append(i)
            ext.append(q[i, cols])
    return np.array(ext), np.array(idx)


def _sinusoid(parts, i, j, cols):
    """Mean, half difference, sxy, trace of steps ``i`` minus those of ``j`` (None: step i)."""
    mean, half, sxy, trace = parts
    a, b, d, t = mean[i, cols], half[i, cols], sxy[i, cols], trace[i, cols]
    if j is not None:
        a, b, d, t = a - mean[j, cols], b - half[j, cols], d - sxy[j, cols], t - trace[j, cols]
    return a, b, d, t


def piece(crit, parts, idx, c, s, E, nu):
    """Value, first and second derivative in 2theta of ``crit`` on the pieces ``idx`` (6, P)
    at (cos, sin) 2theta ``c``, ``s``: the closed form, no pass over the steps."""
    cols = np.arange(c.size)
    a = 1.0 + nu
    name = crit.name
    if name in ("swt", "stress_life", "findley", "fatemi_socie"):
        m, h, xy, _ = _sinusoid(parts, idx[0], None, cols)
        S = m + h * c + xy * s
        S1 = xy * c - h * s
        S2 = m - S
    if name in ("swt", "strain_life"):
        m, h, xy, tr = _sinusoid(parts, idx[2], idx[3], cols)
        R = (a * (m + h * c + xy * s) - nu * tr) / (2.0 * E)
        R1 = a * (xy * c - h * s) / (2.0 * E)
        R2 = a * (m - (m + h * c + xy * s)) / (2.0 * E)
    if name in ("findley", "fatemi_socie", "mwcm"):
        _, h, xy, _ = _sinusoid(parts, idx[4], idx[5], cols)
        T = 0.5 * (xy * c - h * s)
        T1 = 0.5 * (-xy * s - h * c)
        T2 = -T
    if name == "swt":
        return S * R, S1 * R + S * R1, S2 * R + 2.0 * S1 * R1 + S * R2
    if name == "strain_life":
        return R, R1, R2
    if name == "findley":
        k = crit.k
        return T + k * S, T1 + k * S1, T2 + k * S2
    if name == "fatemi_socie":
        f = crit.k / (crit.sy * crit.G)
        u, u1, u2 = 1.0 / crit.G + f * S, f * S1, f * S2
        return T * u, T1 * u + T * u1, T2 * u + 2.0 * T1 * u1 + T * u2
    if name == "mwcm":
        return T, T1, T2
    # stress_life: amplitude A times w(M) = 1 / psi(M) of the mean M
    m, h, xy, _ = _sinusoid(parts, idx[1], None, cols)
    Q = m + h * c + xy * s
    Q1 = xy * c - h * s
    Q2 = m - Q
    A, A1, A2 = 0.5 * (S - Q), 0.5 * (S1 - Q1), 0.5 * (S2 - Q2)
    M, M1, M2 = 0.5 * (S + Q), 0.5 * (S1 + Q1), 0.5 * (S2 + Q2)
    correction = crit.mean_stress
    if correction.name == "none":
        return A, A1, A2
    L = correction.limit
    if correction.name == "gerber":
        psi, p1, p2 = 1.0 - (M / L) ** 2, -2.0 * M / L**2, -2.0 / L**2
    else:
        psi, p1, p2 = 1.0 - M / L, -1.0 / L + 0.0 * M, 0.0
    with np.errstate(divide="ignore", invalid="ignore"):
        w = np.where(psi > 0.0, 1.0 / psi, np.nan)
        w1 = -p1 * w * w
        w2 = (2.0 * p1 * p1 - psi * p2) * w * w * w
    return A * w, A1 * w + A * w1 * M1, A2 * w + 2.0 * A1 * w1 * M1 + A * (w2 * M1 * M1 + w1 * M2)


def _piece_max(crit, parts, idx, phi, lo, hi, E, nu):
    """The offset in [lo, hi] (P,) from ``phi`` of the piece's maximum: safeguarded Newton.

    The bracket closes on the side the slope points away from; a Newton step that leaves it,
    or a point where the piece is not concave, bisects it instead."""
    x = np.zeros_like(phi)
    lo, hi = lo.copy(), hi.copy()
    live = np.ones(phi.shape, dtype=bool)
    for _ in range(NEWTON_STEPS):
        if not live.any():
            break
        c, s = np.cos(phi + x), np.sin(phi + x)
        f, f1, f2 = piece(crit, parts, idx, c, s, E, nu)
        live &= np.isfinite(f) & np.isfinite(f1) & (f1 != 0.0)
        lo = np.where(live & (f1 > 0.0), x, lo)
        hi = np.where(live & (f1 < 0.0), x, hi)
        with np.errstate(divide="ignore", invalid="ignore"):
            newton = x - f1 / f2
        inside = (f2 < 0.0) & (newton > lo) & (newton < hi)
        step = np.where(inside, newton, 0.5 * (lo + hi)) - x
        step = np.where(live, step, 0.0)
        x = x + step
        live &= np.abs(step) > ASCENT_TOLERANCE
    return x


def ascend(crit, better, stress, theta, reach, E, nu, passes, probe=PROBE):
    """Each point's plane of ``crit`` from ``theta`` (P,) within ``reach`` (rad, in theta):
    the angles and the extremes (6, P) on them; at most ``passes`` evaluations after the
    start. ``better(new, new2, old, old2, scale)`` ranks two planes' values (MWCM: ties by
    sigma_n max)."""
    parts = _parts(stress, nu)
    centre = 2.0 * theta
    ext, idx = line_extremes(parts, np.cos(centre), np.sin(centre), nu)
    value = _value(crit, ext, E)
    scale = np.maximum(np.abs(value), 1e-300)
    phi = centre.copy()
    EVALUATIONS[0] += 3 * phi.size  # the start and its two probes
    EVALUATIONS[1] += phi.size
    if passes == 0:
        return 0.5 * phi, ext
    uses = list(piece_uses(crit.name))
    lo, hi = centre - 2.0 * reach, centre + 2.0 * reach
    # the two probes: the best of the three planes starts the ascent
    for side in (-1.0, 1.0):
        at = centre + side * probe * 2.0 * reach
        e, i = line_extremes(parts, np.cos(at), np.sin(at), nu)
        v = _value(crit, e, E)
        move = np.isfinite(value) & better(v, e[0], value, ext[0], scale)
        phi = np.where(move, at, phi)
        value = np.where(move, v, value)
        ext = np.where(move, e, ext)
        idx = np.where(move, i, idx)
    lo = centre - 2.0 * reach - phi
    hi = centre + 2.0 * reach - phi
    live = np.isfinite(value)
    for _ in range(passes):
        if not live.any():
            break
        dx = _piece_max(crit, parts, idx, phi, lo, hi, E, nu)
        live &= np.abs(dx) > ASCENT_TOLERANCE
        EVALUATIONS[0] += live.sum()
        new = phi + dx
        next_ext, next_idx = line_extremes(parts, np.cos(new), np.sin(new), nu)
        next_value = _value(crit, next_ext, E)
        move = live & better(next_value, next_ext[0], value, ext[0], scale)
        same = np.all(next_idx[uses] == idx[uses], axis=0)
        # not better: the maximum is not this piece's; halve the reach towards it
        stay = live & ~move
        hi = np.where(stay & (dx > 0), 0.5 * dx, hi - np.where(move, dx, 0.0))
        lo = np.where(stay & (dx < 0), 0.5 * dx, lo - np.where(move, dx, 0.0))
        phi = np.where(move, new, phi)
        value = np.where(move, next_value, value)
        ext = np.where(move, next_ext, ext)
        idx = np.where(move, next_idx, idx)
        live &= ~(move & same)
    return 0.5 * phi, ext


def _value(crit, ext, E) -> np.ndarray:
    """The criterion's value from the extremes (6, P) of :func:`line_extremes`."""
    q = {
        "normal_stress_max": ext[0],
        "normal_stress_min": ext[1],
        "normal_strain_amplitude": 0.5 * (ext[2] - ext[3]) / E,
    }
    return crit.value(q, 0.5 * (ext[4] - ext[5]))


def grid_planes(stress, criteria, E, nu):
    """Each criterion's best plane of the search's 5-degree in-plane grid (radians)."""
    theta, psi = cp.plane_grid(in_plane_only=True, theta_step_deg=5.0, psi_step_deg=10.0)
    columns = cp._coarse_columns(theta, psi, nu, strains=True, shear=True, in_plane=True)
    best = cp._coarse(stress, criteria, columns, theta.size, E, True)
    return {name: theta[i] for name, i in best.items()}


def ascent_values(stress, methods, mean_stress, kw):
    """Each criterion's value at every point by the ascent from its grid plane."""
    criteria = cp._make_criteria(
        methods, kw["E"], kw["nu"], kw["findley_k"], kw["fatemi_socie_k"],
        kw["yield_strength"], mean_stress,
    )  # fmt: skip
    start = grid_planes(stress, criteria, kw["E"], kw["nu"])
    out = {}
    for crit in criteria:
        _, ext = ascend(crit, functools.partial(cp._better, crit), stress, start[crit.name],
                        np.deg2rad(5.0), kw["E"], kw["nu"], 5)  # fmt: skip
        out[crit.name] = _value(crit, ext, kw["E"])
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=30, help="points per history")
    args = parser.parse_args()
    worst: dict = {}
    for _name, stress in fa.histories(args.points).items():
        for label, correction in fa.CORRECTIONS.items():
            methods = METHODS if correction is None else ("stress_life",)
            ref, _ = in_plane_scan(stress, E=fa.E, nu=fa.NU, step_deg=0.01,
                                   mean_stress=correction)  # fmt: skip
            search = critical_plane_parameters(
                stress, methods=methods, mean_stress=correction,
                search=PlaneSearch(in_plane_only=True, compiled=False), **fa.KW,
            )  # fmt: skip
            ascent = ascent_values(stress, methods, correction, fa.KW)
            for method in ascent:
                row = method if correction is None else f"{method} {label}"
                for kind, value in (("search", search[method].value), ("ascent", ascent[method])):
                    finite = np.isfinite(ref[method]) & np.isfinite(value)
                    scale = np.abs(ref[method][finite]).max(initial=1e-300)
                    gap = (ref[method][finite] - value[finite]) / scale
                    w = worst.setdefault((row, kind), [0.0, 0.0])
                    w[0] = max(w[0], gap.max(initial=0.0))
                    w[1] = max(w[1], -gap.min(initial=0.0))
    print(f"{'criterion':<22}{'search short':>14}{'over':>10}{'ascent short':>14}{'over':>10}")
    for row in sorted({r for r, _ in worst}):
        p, a = worst[(row, "search")], worst[(row, "ascent")]
        print(f"{row:<22}{p[0]:14.2e}{p[1]:10.2e}{a[0]:14.2e}{a[1]:10.2e}")
    print(f"evaluations per criterion and point: the search 9 in-plane (7 compiled), ascent "
          f"{EVALUATIONS[0] / max(EVALUATIONS[1], 1):.2f}")  # fmt: skip
    stress = fph.stress_cycle()
    kw = {"E": 116000.0, "nu": 0.342, **fph.CONSTANTS}
    runs = {
        "the search (numpy)": lambda: critical_plane_parameters(
            stress, methods=METHODS[:4],
            search=PlaneSearch(in_plane_only=True, compiled=False), **kw),
        "grid + ascent (numpy)": lambda: ascent_values(stress, METHODS[:4], None, kw),
    }  # fmt: skip
    for name, fn in runs.items():
        fn()
        times = []
        for _ in range(5):
            t = time.process_time()
            fn()
            times.append(time.process_time() - t)
        print(f"{name}, 10,000 points, 4 criteria: {min(times) * 1e3:.0f} ms CPU (least of 5)")


if __name__ == "__main__":
    main()
