"""Checks every result must pass before it is reported, and up-front input and resource checks.

Each check is a pure function of arrays (no solver or body objects), returns a
:class:`CheckRecord` with its residual so runs can record it in ``summary.json``, and raises
a named :class:`ResultCheckError` subclass whose message names the cause and the fix.
Errors and tolerances are *fractions* (0.01 means 1 %), as everywhere in fretbem's files.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Sequence

import attrs
import numpy as np

from fretbem.errors import InputError, ResultCheckError, SolverSettingsError

SEPARATED, STICK, SLIP = 0, 1, 2

#: |integral of p - P| / P and |integral of q - Q| / P allowed after an increment. Measured:
#: 5e-5 (p) and 7e-5 (q) on the reference scene with 31 nurbs pairs; 1e-3 leaves a margin.
EQUILIBRIUM_TOLERANCE = 1e-3
#: a pad displaced tangentially by more than this many contact-zone widths is not held
RUNAWAY_FACTOR = 10.0
#: Newton systems with a larger condition number do not determine the block position
MAX_CONDITION = 1e12
#: largest accepted Newton tolerance: a looser one reports unconverged tractions as results
MAX_SOLVER_TOLERANCE = 1e-3


class EquilibriumError(ResultCheckError):
    """The contact tractions do not balance the applied loads."""

    check = "equilibrium"


class ContactZoneError(ResultCheckError):
    """The outermost pairs of the candidate zone are in contact: the zone is too small."""

    check = "zone_edge"


class TangentialIndeterminacyError(ResultCheckError):
    """Nothing holds the body tangentially (no stick pair, or a singular Newton system)."""

    check = "tangential_hold"


class ConsistencyError(ResultCheckError):
    """A result's reported arrays are not those its solved unknowns give (edited after the
    solve): it must not be written beside checks that passed on other numbers."""

    check = "consistency"


class StepNameError(InputError):
    """Load step names that are missing, duplicated or not text."""


@attrs.frozen
class CheckRecord:
    """Outcome of one check: name, measured residual, allowed limit, and whether it passed."""

    check: str
    residual: float
    limit: float
    passed: bool

    def as_dict(self) -> dict:
        """JSON-ready form (residual and limit as floats; NaN becomes None)."""

        def clean(v: float):
            return None if math.isnan(v) else v

        return {"residual": clean(self.residual), "limit": clean(self.limit), "passed": self.passed}


def _span(x: np.ndarray) -> float:
    """max - min of a non-empty ``x``: np.ptp's number, without its three frames."""
    return float(np.maximum.reduce(x) - np.minimum.reduce(x))


@attrs.frozen(eq=False)
class PairPositions:
    """What the result checks read of the pair positions alone, taken once for the steps
    of a run (its pairs do not move): the typical spacing and the outermost pairs."""

    spacing: float
    #: the indices of the first and the last pair along x (argsort's ends)
    ends: np.ndarray


def pair_positions(x: np.ndarray) -> PairPositions:
    """The :class:`PairPositions` of the pair positions ``x``."""
    x = np.asarray(x, float)
    ends = np.argsort(x)[[0, -1]] if len(x) else np.zeros(0, dtype=int)
    return PairPositions(_spacing(x), ends)


def _spacing(x: np.ndarray) -> float:
    """Typical pair spacing: the median distance between neighbouring pairs (np.median's
    number, the middle one or the mean of the middle two, without its ~50 us of checks)."""
    if len(x) < 2:
        return math.nan
    ordered = np.sort(x)
    gaps = np.sort(ordered[1:] - ordered[:-1])  # np.diff's numbers without its frame
    middle = gaps.size // 2
    return float(gaps[middle] if gaps.size % 2 else (gaps[middle - 1] + gaps[middle]) / 2.0)


# -- result checks: call after every increment, before anything is written -------------------
def equilibrium(
    integral_p: float,
    integral_q: float,
    normal: float,
    tangential: float,
    *,
    step: str = "",
    tolerance: float = EQUILIBRIUM_TOLERANCE,
    raise_error: bool = True,
    hint: str = "",
) -> CheckRecord:
    """Integral of p equals P and of q equals Q, within ``tolerance`` x P.

    Both residuals are scaled by P (the load that sets the contact size), so Q = 0 steps are
    checked as strictly as loaded ones. Raises :class:`EquilibriumError` when violated
    (``hint``, a likelier cause, is added to its message).
    """
    scale = abs(float(normal))
    values = (integral_p, integral_q, normal, tangential)
    if not all(math.isfinite(float(v)) for v in values) or scale == 0:
        residual = math.inf
    else:
        residual = max(abs(integral_p - normal), abs(integral_q - tangential)) / scale
    record = CheckRecord("equilibrium", residual, tolerance, residual <= tolerance)
    if raise_error and not record.passed:
        raise EquilibriumError(
            f"step {step!r}: the contact tractions do not balance the loads: integral of p = "
            f"{integral_p:.6g} for P = {normal:.6g}, integral of q = {integral_q:.6g} for "
            f"Q = {tangential:.6g} (residual {residual:.3g} x P, allowed {tolerance:.3g}); refine "
            "the contact zone (more pairs) or the mesh, or check that E and the loads are of "
            f"comparable magnitude (units mm, N, MPa){hint}",
            residual,
        )
    return record


def resultant_balance(
    resultants: Sequence[Sequence[float]],
    scale: float,
    *,
    step: str = "",
    tolerance: float = EQUILIBRIUM_TOLERANCE,
    raise_error: bool = True,
) -> CheckRecord:
    """Each body's force resultants (contact + supports + loads, one (2,) per body) sum to 0.

    ``scale`` is the load magnitude (P). Raises :class:`EquilibriumError` when violated.
    """
    forces = np.asarray(resultants, dtype=float).reshape(-1, 2)
    if scale <= 0 or not np.all(np.isfinite(forces)):
        residual = math.inf
    else:
        residual = float(np.max(np.abs(forces))) / scale if len(forces) else 0.0
    record = CheckRecord("body_balance", residual, tolerance, residual <= tolerance)
    if raise_error and not record.passed:
        worst = int(np.argmax(np.abs(forces).max(axis=1))) if len(forces) else 0
        raise EquilibriumError(
            f"step {step!r}: body {worst}'s forces do not balance (largest unbalanced component "
            f"{residual:.3g} x P, allowed {tolerance:.3g}); refine the mesh near the supports "
            "and the contact, or tighten the solver tolerance",
            residual,
        )
    return record


def zone_edge(
    x: np.ndarray,
    states: np.ndarray,
    pressure: np.ndarray | None = None,
    *,
    step: str = "",
    raise_error: bool = True,
    hint: str = "",
    positions: PairPositions | None = None,
) -> CheckRecord:
    """The outermost pair at each end of the candidate zone must be separated.

    If it is in contact, the true contact may extend beyond the zone and the pressure there
    is an artefact of the truncation. The residual is the number of in-contact end pairs.
    Raises :class:`ContactZoneError` naming ``zone``. ``positions``: :func:`pair_positions`
    of ``x``, taken once for a run's steps.
    """
    x, states = np.asarray(x, float), np.asarray(states)
    if len(states) == 0:
        return CheckRecord("zone_edge", 0.0, 0.0, True)
    ends = (positions or pair_positions(x)).ends
    touching = [int(k) for k in ends if states[k] != SEPARATED]
    record = CheckRecord("zone_edge", float(len(set(touching))), 0.0, not touching)
    if raise_error and not record.passed:
        where = ", ".join(
            f"x = {x[k]:.4g} mm"
            + (f" (p = {float(pressure[k]):.4g} MPa)" if pressure is not None else "")
            for k in sorted(set(touching))
        )
        raise ContactZoneError(
            f"step {step!r}: the outermost pair of the candidate contact zone is in contact at "
            f"{where}, so the real contact may be wider than the zone; enlarge the scene's "
            f"`zone` (the candidate zone half-width) until its end pairs are separated{hint}",
            record.residual,
        )
    return record


def _hold_advice(ratio: float, width: float, spacing: float) -> str:
    """What makes the stick zone resolvable: its expected width (Cattaneo-Mindlin, c/a =
    sqrt(1 - |Q|/(f P))) against the pair spacing, so the advice says how many pairs."""
    if not (0.0 <= ratio < 1.0) or not (width > 0 and spacing > 0):
        return "keep |Q| below f P (the [load] Q values under [contact] friction x P)"
    stick = width * math.sqrt(1.0 - ratio)  # expected stick-zone width, mm
    factor = 3.0 * spacing / stick  # three pairs across the stick zone
    if factor <= 4.0:
        return (
            f"the stick zone should be about {stick:.3g} mm wide: raise [contact] pairs about "
            f"{max(factor, 1.5):.2g} times, or keep |Q| further below f P"
        )
    limit = 1.0 - (3.0 * spacing / width) ** 2
    return (
        f"the stick zone should be only about {stick:.3g} mm wide, which would need about "
        f"{factor:.3g} times the pairs: keep |Q| / (f P) below about {max(limit, 0.0):.3g} "
        "with these pairs (the [load] Q values), or raise [contact] friction"
    )


def tangential_hold(
    x: np.ndarray,
    states: np.ndarray,
    normal: float,
    tangential: float,
    friction: float,
    *,
    block_displacement: float = 0.0,
    condition: float | None = None,
    step: str = "",
    raise_error: bool = True,
    held: bool = False,
    positions: PairPositions | None = None,
) -> CheckRecord:
    """Something must hold the loaded body tangentially: a stick pair and a bounded block move.

    ``held``: the block's tangential displacement was imposed (displacement control), so
    the block holds the body whatever the contact does (gross slip included): the check
    passes with residual 0.

    Near gross sliding (``|Q| -> f P``) the stick zone shrinks below one pair spacing; the
    tangential position is then undetermined and Newton may return an arbitrary (e.g. 1e9 mm)
    block displacement. The residual is the block displacement in contact-zone widths.
    Raises :class:`TangentialIndeterminacyError` with the stick-zone width and the fixes.
    ``positions``: :func:`pair_positions` of ``x``, taken once for a run's steps.
    """
    if held:
        return CheckRecord("tangential_hold", 0.0, RUNAWAY_FACTOR, True)
    x, states = np.asarray(x, float), np.asarray(states)
    in_contact = states != SEPARATED
    stick = states == STICK
    spacing = _spacing(x) if positions is None else positions.spacing
    touching, sticking = np.count_nonzero(in_contact), np.count_nonzero(stick)
    width = _span(x[in_contact]) if touching > 1 else spacing
    width = width if width > 0 else (spacing if math.isfinite(spacing) else 1.0)
    runaway = abs(float(block_displacement)) / width
    if not math.isfinite(runaway):
        runaway = math.inf
    no_stick = touching > 0 and sticking == 0
    singular = condition is not None and not (condition <= MAX_CONDITION)
    ok = not no_stick and runaway <= RUNAWAY_FACTOR and not singular
    record = CheckRecord("tangential_hold", runaway, RUNAWAY_FACTOR, ok)
    if raise_error and not ok:  # (the stick zone's width is the message's alone)
        stick_width = _span(x[stick]) if sticking > 1 else 0.0
        ratio = abs(tangential) / (friction * normal) if friction * normal > 0 else math.inf
        cause = (
            "no pair sticks"
            if no_stick
            else f"the Newton system is singular (condition number {condition:.3g})"
            if singular
            else f"the block moved {block_displacement:.3g} mm ({runaway:.3g} contact widths)"
        )
        raise TangentialIndeterminacyError(
            f"step {step!r}: nothing holds the body tangentially ({cause}): |Q| / (f P) = "
            f"{ratio:.6g}, stick-zone width {stick_width:.4g} mm against a pair spacing of "
            f"{spacing:.4g} mm; {_hold_advice(ratio, width, spacing)}",
            runaway,
        )
    return record


# -- input checks: call before any computation -----------------------------------------------
def solver_settings(tolerance: float, max_iterations: int, max_substeps: int = 0) -> None:
    """Newton tolerance in (0, 1e-3], whole iteration and substep counts (iterations >= 1)."""
    try:
        tol = float(tolerance)
    except (TypeError, ValueError):
        raise SolverSettingsError(f"solver tolerance must be a number, got {tolerance!r}") from None
    if not (0 < tol <= MAX_SOLVER_TOLERANCE):
        raise SolverSettingsError(
            f"solver tolerance {tolerance!r} is outside (0, {MAX_SOLVER_TOLERANCE:g}]: a looser "
            "one reports unconverged tractions; use e.g. 1e-10 (the default)"
        )
    for name, value, least in (
        ("max_iterations", max_iterations, 1),
        ("max_substeps", max_substeps, 0),
    ):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < least:
            raise SolverSettingsError(
                f"solver {name} must be a whole number >= {least}, got {value!r}"
            )


def step_names(names: Iterable[object]) -> tuple[str, ...]:
    """Step names must be non-empty text without NUL and unique; returns them as a tuple."""
    names = tuple(names)
    for name in names:
        if not isinstance(name, str) or not name.strip() or "\0" in name:
            raise StepNameError(
                f"load step name {name!r} must be non-empty text without NUL characters"
            )
    seen: set[str] = set()
    duplicates = sorted({n for n in names if n in seen or seen.add(n)})
    if duplicates:
        raise StepNameError(
            f"load step names must be unique (results and files are keyed by them); repeated: "
            f"{duplicates}; rename the steps, e.g. B1, B2"
        )
    return names


# -- file names ---------------------------------------------------------------------------------
_UNSAFE = re.compile(r"[^A-Za-z0-9._-]+")
MAX_NAME = 64


def safe_names(names: Sequence[str]) -> list[str]:
    """File-name stems for user names: only ``[A-Za-z0-9._-]``, no leading dot, <= 64 chars, unique.

    ``../../x`` -> ``x``, ``/abs/path`` -> ``abs_path``, ``B/1`` -> ``B_1``; collisions get
    ``-2``, ``-3`` suffixes, so a stem can never leave its directory or overwrite a sibling.
    """
    out: list[str] = []
    used: set[str] = set()
    for k, name in enumerate(names):
        stem = _UNSAFE.sub("_", str(name)).strip("._-")
        stem = re.sub(r"\.{2,}", ".", stem)[:MAX_NAME] or f"step{k}"
        candidate, n = stem, 1
        while candidate.lower() in used:
            n += 1
            candidate = f"{stem[: MAX_NAME - len(str(n)) - 1]}-{n}"
        used.add(candidate.lower())
        out.append(candidate)
    return out


# -- all result checks of a finished run ------------------------------------------------------
def check_steps(
    result, *, raise_error: bool = True, fresh: bool = False
) -> list[dict[str, CheckRecord]]:
    """Run every result check on every step of ``result`` (a SimulationResult).

    Returns per step {check name: CheckRecord}; raises the first failure's named error when
    ``raise_error``. Used before any output is written (fretbem.output) and by the CLI.
    ``fresh``: ``result`` comes straight from the solve, whose run checked every step it
    gave ``checks`` (:func:`fretbem.simulation.run`) and which nothing could edit since:
    those steps are not checked again.
    """
    if fresh and all(s.checks is not None for s in result.steps):
        return [s.checks for s in result.steps]
    consistent(result)
    friction = float(result.describe().get("friction", math.nan))
    return [check_step(s, friction, raise_error=raise_error) for s in result.steps]


def consistent(result) -> None:
    """The tractions and resultants reported are those of the solved unknowns.

    The checks run on the step's resultant (from the unknowns) while the writers write its
    ``pressure`` and ``shear``: a result whose arrays were replaced after the solve (e.g.
    ``attrs.evolve(step, pressure=2 * p)``) is refused here instead of being written beside
    checks that passed on the original numbers.
    """
    try:
        problem = result.simulation.prepare()
        force_map = problem.lower_force_map
        normal, tangent = result.simulation.frame()
    except AttributeError:  # a result without its simulation: arrays only
        problem = None
    for step in result.steps:
        if step.layout is None:
            continue
        unknowns = step.pair_unknowns
        for name, solved in (("pressure", unknowns.pressure), ("shear", unknowns.shear)):
            written = np.asarray(getattr(step, name), float)
            if written.shape != np.shape(solved) or not np.allclose(
                written, solved, rtol=1e-12, atol=1e-12 * max(1.0, float(np.max(np.abs(solved))))
            ):
                raise ConsistencyError(
                    f"step {step.name!r}: its {name} is not the one its solved unknowns give "
                    "(the result was edited after the solve); re-run the simulation instead "
                    "of editing a result"
                )
        if problem is None:
            continue
        own = getattr(step, "pair", None)  # a sliding run's step: solved on its own pairing
        if own is not None:
            step_map = own.condensed().lower_force_map
            step_normal, step_tangent = own.pairing().load_frame()
        else:
            step_map, step_normal, step_tangent = force_map, normal, tangent
        if np.size(step.unknowns) == step_map.shape[1]:
            force = step_map @ np.asarray(step.unknowns, float)
            resultant = (float(-force @ step_normal), float(force @ step_tangent))
            scale = max(abs(step.normal), abs(step.tangential), 1e-300)
            if max(abs(a - b) for a, b in zip(resultant, step.resultant, strict=True)) > (
                1e-9 * scale
            ):
                raise ConsistencyError(
                    f"step {step.name!r}: its resultant {step.resultant} is not the one its "
                    f"unknowns give {resultant} (the result was edited after the solve)"
                )


def _turning_hint(step) -> str:
    """For a step whose pad block turns: the rotation as the likelier cause of a failed
    equilibrium or zone check (a moment the contact cannot carry moves it off the zone)."""
    tilt = getattr(step, "tilt", 0.0)
    by_moment = getattr(getattr(step, "controls", None), "rotation", "rotation") == "moment"
    if not by_moment and not tilt:
        return ""
    return (
        f"; the pad block turns here (tilt {tilt:.3g} rad, M = {step.moment:.4g} N mm/mm): a "
        "moment or rotation the contact cannot balance moves the contact out of the zone, so "
        "check [load] moment or rotation and [rig] stiffness_rotation and pivot_height first"
    )


def check_step(
    step, friction: float, *, raise_error: bool = True, positions: PairPositions | None = None
) -> dict[str, CheckRecord]:
    """Every result check of one StepResult: equilibrium, zone edge, tangential hold.

    The tangential hold is checked first: a body nothing holds tangentially has a block
    displacement and tractions set by round-off, whose equilibrium residual then depends on
    the assembly's last bits; its own message names the cause (near gross sliding).
    ``positions``: :func:`pair_positions` of the step's ``x``, taken once for a run's steps."""
    blocks = _block_displacements(step)
    block = float(np.maximum.reduce(np.abs(blocks))) if blocks.size else 0.0
    hint = _turning_hint(step)
    hold = tangential_hold(
        step.x, step.states, step.normal, step.tangential, friction,
        block_displacement=block, step=step.name, raise_error=raise_error,
        held=getattr(getattr(step, "controls", None), "tangential", "force") != "force",
        positions=positions,
    )  # fmt: skip
    return {
        "equilibrium": equilibrium(
            step.resultant[0], step.resultant[1], step.normal, step.tangential, step=step.name,
            raise_error=raise_error, hint=hint,
        ),
        "zone_edge": zone_edge(
            step.x, step.states, step.pressure, step=step.name, raise_error=raise_error,
            hint=hint, positions=positions,
        ),
        "tangential_hold": hold,
    }  # fmt: skip


def _block_displacements(step) -> np.ndarray:
    """Every block displacement of ``step``'s unknowns, in layout order (the slice of x the
    layout puts them in, where x fits the layout; else through ``pair_unknowns``, which
    names the mismatch)."""
    layout, x = step.layout, step.unknowns
    if layout is not None and np.shape(x) == (layout.size,):
        start = 2 * layout.n_pairs
        return np.asarray(x, float)[start : start + 2 * len(layout.blocks)]
    return np.concatenate([np.zeros(0), *step.pair_unknowns.blocks.values()])
