"""Per-step results of a contact simulation (read-only arrays) and the run's result.

The errors against theory are computed by :mod:`fretbem.verification.errors`."""

from __future__ import annotations

import attrs
import numpy as np

from fretbem.contact import control
from fretbem.contact.law import STATE_NAMES
from fretbem.contact.unknowns import PairUnknowns, UnknownLayout
from fretbem.contact.zones import StepZones, step_zones
from fretbem.verification.errors import ERROR_KEYS, errors_against_theory
from fretbem.verification.theory import hertz_numbers, theory_stick_zones
from fretbem.views.display import result_html, result_repr, step_html, step_repr
from fretbem.views.run import run_dataset


def _frozen(values) -> np.ndarray:
    """A read-only copy: a result reports what was computed, and cannot be edited in place
    (an array already frozen, read-only float64 owning its numbers or a read-only view of
    such an array, is taken as it is: a step shares its last increment's arrays, a run's
    steps their positions, and a record the run's frozen pair unknowns and their slices)."""
    if _owned_read_only(values, np.float64):
        return values
    out = np.array(values, dtype=float)
    out.setflags(write=False)
    return out


def _frozen_states(values) -> np.ndarray:
    if _owned_read_only(values, None):
        return values
    out = np.array(values)
    out.setflags(write=False)
    return out


def _owned_read_only(values, dtype) -> bool:
    """Whether ``values`` is an ndarray (of ``dtype``, if given) that cannot be written and
    owns its numbers, or views those of one that owns them and cannot be written (no
    writable array shares them: neither can be made writable again from the view)."""
    if type(values) is not np.ndarray or values.flags.writeable:
        return False
    if dtype is not None and values.dtype != dtype:
        return False
    base = values.base
    return base is None or (
        type(base) is np.ndarray and base.base is None and not base.flags.writeable
    )


def pair_x(problem) -> np.ndarray:
    """The pairs' positions along x (the lower body's), read-only: the same for every step
    of a run on ``problem`` (:meth:`StepResult.build` takes them once)."""
    return _frozen(problem.pairing.points[:, 0])


class _Mapping:
    """Read access by key (``record["levels"]``, ``.get``, ``in``) for one release: these
    records were string-keyed dicts."""

    def as_dict(self) -> dict:
        raise NotImplementedError

    def __getitem__(self, key: str):
        data = self.as_dict()
        if key not in data:
            raise KeyError(key)
        return data[key]

    def get(self, key: str, default=None):
        return self.as_dict().get(key, default)

    def __contains__(self, key: str) -> bool:
        return key in self.as_dict()

    def keys(self):
        return self.as_dict().keys()

    def __iter__(self):
        return iter(self.as_dict())


@attrs.frozen
class Estimate(_Mapping):
    """Estimated discretisation error of one step, fractions of p0 and f p0 (the keys of
    the errors against theory: e_p_max, e_q_max, e_p_l2, e_q_l2)."""

    e_p_max: float
    e_q_max: float
    e_p_l2: float
    e_q_l2: float

    @classmethod
    def of(cls, values) -> Estimate:
        """From a mapping with the four keys."""
        return cls(**{k: float(values[k]) for k in ERROR_KEYS})

    def as_dict(self) -> dict:
        return {k: getattr(self, k) for k in ERROR_KEYS}


@attrs.frozen
class AccuracyRecord(_Mapping):
    """How a run's accuracy was obtained (summary.json's ``accuracy``).

    Attributes
    ----------
    mesh : str
        "fixed" or "adaptive".
    levels : tuple of int
        Pairs of every level solved; the last is the result.
    seconds : float or None
        Time of all levels.
    estimate_reason : str or None
        Why there is no estimate (None when there is one).
    rate, factor : float or None
        The fixed mode's assumed convergence rate and its Richardson factor.
    tolerance, budget, transitions : optional
        The adaptive mode's settings and the transitions it found.
    caution : str or None
        A warning that the result lies outside what was verified.
    """

    mesh: str
    levels: tuple = attrs.field(converter=lambda v: tuple(int(n) for n in v))
    seconds: float | None = None
    estimate_reason: str | None = None
    rate: float | None = None
    factor: float | None = None
    tolerance: float | None = None
    budget: int | None = None
    transitions: object = None
    caution: str | None = None

    def as_dict(self) -> dict:
        """The summary.json table: optional entries only where they apply."""
        out = {"mesh": self.mesh, "levels": list(self.levels)}
        for name in ("seconds", "tolerance", "budget", "transitions"):
            if getattr(self, name) is not None:
                out[name] = getattr(self, name)
        out["estimate_reason"] = self.estimate_reason
        for name in ("rate", "factor", "caution"):
            if getattr(self, name) is not None:
                out[name] = getattr(self, name)
        return out


def _gross_sliding(reference, history) -> bool:
    """Whether a tangential history (imposed by displacement) reached f P: the partial-slip
    closed forms then no longer apply (unless the reference follows sliding)."""
    if getattr(reference, "slides", False):
        return False
    limit = reference.friction * reference.hertz.load * (1.0 - 1e-9)
    return any(abs(value) >= limit for value in np.asarray(history, float).tolist())


@attrs.frozen(eq=False)
class IncrementRecord:
    """What one load increment reached: the block's loads and motion and the pair fields.

    Attributes
    ----------
    normal, tangential : float
        P and Q carried by the pad's loading block (force per thickness).
    approach, delta : float
        Normal approach and tangential displacement of the pad's block against the datum
        (the specimen's held end; :mod:`fretbem.contact.control`), mm; the actuator's
        when the simulation has rig springs.
    slip : ndarray
        Relative tangential displacement (upper minus lower) per pair, mm.
    pressure, shear : ndarray
        p and q per pair.
    states : ndarray of int
        0 separated, 1 stick, 2 slip.
    loads : dict
        Named load amplitudes.
    moment : float
        M, the moment of the pad's block on the pad about the rig's pivot (N mm/mm,
        counterclockwise); NaN where the pad's model gives none.
    rotation, tilt : float
        The actuator's rotation theta (rad, counterclockwise; the block's plus M / k_r) and
        the pad block's own (0 when the block does not rotate).
    """

    normal: float
    tangential: float
    approach: float
    delta: float
    slip: np.ndarray = attrs.field(converter=_frozen)
    pressure: np.ndarray = attrs.field(converter=_frozen)
    shear: np.ndarray = attrs.field(converter=_frozen)
    states: np.ndarray = attrs.field(converter=_frozen_states)
    loads: dict = attrs.field(factory=dict)
    moment: float = float("nan")
    rotation: float = 0.0
    tilt: float = 0.0

    @classmethod
    def of(cls, problem, state, rig=control.RIGID) -> IncrementRecord:
        """The record of ``state`` (a ContactState) of the condensed ``problem``."""
        x, layout = state.x, problem.layout
        if np.shape(x) != (layout.size,):  # (the layout's own error names the mismatch)
            problem.unknowns(x)
        measured = control.measure(problem, x, problem.amplitudes(state.loads), rig)
        return cls(
            normal=measured["normal"],
            tangential=measured["tangential"],
            approach=measured["approach"],
            delta=measured["delta"],
            slip=state.slip,
            pressure=x[layout.pressure],  # (PairUnknowns.from_vector's views, without it)
            shear=x[layout.shear],
            states=state.states,
            loads=dict(state.loads),
            moment=measured["moment"],
            rotation=measured["rotation"],
            tilt=measured["tilt"],
        )


class _Deferred:
    """A step's errors against theory and exact tractions, computed when first read: the
    steps of a run that never reads them (a sweep, a benchmark, a study of other numbers)
    skip the closed forms (about a twentieth of a 61-pair half-plane cycle). Holds the
    step's own positions and tractions, so whichever copy of the step reads first gets the
    numbers the step was built with."""

    def __init__(self, reference, x: np.ndarray, p: np.ndarray, q: np.ndarray, history):
        self.inputs = (reference, x, p, q, tuple(history))
        self.value: tuple | None = None

    def get(self) -> tuple[dict, tuple[np.ndarray, np.ndarray]]:
        """(errors, exact) of :func:`~fretbem.verification.errors.errors_against_theory`."""
        if self.value is None:
            self.value = errors_against_theory(*self.inputs)
            self.inputs = None
        return self.value


@attrs.frozen(eq=False)
class StepResult:
    """Everything reported for one load step.

    Attributes
    ----------
    name : str
    normal, tangential : float
        P and Q at the end of the step.
    x, pressure, shear : ndarray
        Pair positions (lower body, x coordinate) and the tractions there.
    normal_displacement, tangential_displacement : ndarray
        Relative displacements (upper minus lower) in the pair frame.
    states : ndarray of int
        0 separated, 1 stick, 2 slip.
    iterations : int
    residuals : tuple of float
    seconds : float
    unknowns : ndarray
        Raw pair unknowns (p, q, block displacements); :attr:`pair_unknowns` names them.
    layout : UnknownLayout
        The order of ``unknowns``.
    loads : dict
        Named load amplitudes at the end of the step.
    resultant : (float, float)
        Integrals of p and q over the contact segment (from the traction field).
    errors : dict or None
        e_p, e_q (max and L2), normalised by p0 and f p0; None without a reference
        (computed when first read).
    exact : (ndarray, ndarray) or None
        The reference's p and q at ``x`` (computed with ``errors``).
    checks : dict or None
        The result checks this step passed (name -> CheckRecord with its residual), set by
        :func:`fretbem.simulation.run`.
    estimate : dict or None
        Estimated discretisation error (the keys of ``errors``, fractions of p0 and f p0),
        set by :func:`fretbem.accuracy.modes.solve`; None without an estimate.
    controls : Controls
        Which directions of the pad's block the step drove by displacement.
    approach, delta : float
        Normal approach and tangential displacement of the pad's block against the datum
        (the specimen's held end), mm, at the end of the step.
    increments : tuple of IncrementRecord
        Every increment of the step, in order (set by :func:`fretbem.simulation.run`).
    pair : ContactPair or None
        Finite sliding: the pairing the step was solved with (the pad where it had slid);
        None: the simulation's own pair.
    moment : float
        M, the moment the pad's block applies to the pad about the rig's pivot (N mm/mm,
        counterclockwise; :mod:`fretbem.contact.rotation`); NaN where the pad's model
        gives none.
    rotation, tilt : float
        The actuator's rotation theta (rad, counterclockwise: the block's plus M / k_r) and
        the pad block's own rotation (both 0 when the block does not rotate).
    """

    name: str
    normal: float
    tangential: float
    x: np.ndarray = attrs.field(converter=_frozen)
    pressure: np.ndarray = attrs.field(converter=_frozen)
    shear: np.ndarray = attrs.field(converter=_frozen)
    normal_displacement: np.ndarray = attrs.field(converter=_frozen)
    tangential_displacement: np.ndarray = attrs.field(converter=_frozen)
    states: np.ndarray = attrs.field(converter=_frozen_states)
    iterations: int
    residuals: tuple[float, ...]
    seconds: float
    unknowns: np.ndarray = attrs.field(converter=_frozen)
    resultant: tuple[float, float]
    #: dict or None, or the _Deferred that computes both when first read
    _errors: dict | _Deferred | None = attrs.field(alias="errors", repr=False)
    _exact: tuple[np.ndarray, np.ndarray] | _Deferred | None = attrs.field(
        alias="exact", repr=False
    )
    layout: UnknownLayout | None = None
    loads: dict = attrs.field(factory=dict)
    checks: dict | None = None
    estimate: Estimate | None = None
    controls: control.Controls = attrs.field(factory=control.Controls)
    approach: float = float("nan")
    delta: float = float("nan")
    increments: tuple = ()
    pair: object = None
    moment: float = float("nan")
    rotation: float = 0.0
    tilt: float = 0.0

    def __repr__(self) -> str:
        return step_repr(self)

    def _repr_html_(self) -> str:
        return step_html(self)

    @property
    def errors(self) -> dict | None:
        """e_p, e_q (max and L2), normalised by p0 and f p0; None without a reference."""
        value = self._errors
        return value.get()[0] if isinstance(value, _Deferred) else value

    @property
    def exact(self) -> tuple[np.ndarray, np.ndarray] | None:
        """The reference's p and q at ``x``; None without a reference."""
        value = self._exact
        return value.get()[1] if isinstance(value, _Deferred) else value

    @property
    def pair_unknowns(self) -> PairUnknowns:
        """``unknowns`` split by name (pressure, shear, block displacements)."""
        return PairUnknowns.from_vector(self.unknowns, self.layout)

    @classmethod
    def build(
        cls, simulation, problem, load, state, iterations, residuals, seconds, history, *,
        last: IncrementRecord | None = None, increments: tuple = (), checks=None, x=None,
    ):  # fmt: skip
        """Collect a step's pair results, resultants and errors against the reference.

        ``last``, the record of the step's last increment (the same state), gives the
        block's measured approach, delta, moment and rotation without measuring again, and
        its tractions, slip and states; ``increments``, every increment's record, are kept
        as they are; ``checks(step)`` gives the record's :attr:`checks` (None: none);
        ``x``, :func:`pair_x` of ``problem``, taken once for a run's steps."""
        x = pair_x(problem) if x is None else x
        if last is not None:
            p, q, slip, states = last.pressure, last.shear, last.slip, last.states
        else:
            unknowns = problem.unknowns(state.x)
            p, q = _frozen(unknowns.pressure), _frozen(unknowns.shear)
            slip, states = state.slip, state.states
        force = np.dot(problem.lower_force_map, state.x)  # contact force on the lower body
        normal, tangent = simulation.frame()  # np.dot: `@`'s numbers, with less overhead
        resultant = (float(-np.dot(force, normal)), float(np.dot(force, tangent)))
        errors = exact = None
        if simulation.reference is not None and not _gross_sliding(simulation.reference, history):
            errors = exact = _Deferred(simulation.reference, x, p, q, history)
        if last is not None:  # (its fields read directly: attrs.asdict walks all twelve)
            measured = {"approach": last.approach, "delta": last.delta, "moment": last.moment,
                        "rotation": last.rotation, "tilt": last.tilt}  # fmt: skip
        else:
            rig = getattr(simulation, "rig", control.RIGID)
            measured = control.measure(problem, state.x, problem.amplitudes(state.loads), rig)
        controls = load.controls
        gap = problem.relative_normal(state.x, problem.amplitudes(state.loads))
        gap.setflags(write=False)  # a fresh array: frozen here, the record takes it uncopied
        step = cls(
            name=load.name,
            normal=load.normal if controls.normal == "force" else state.normal,
            tangential=load.tangential if controls.tangential == "force" else state.tangential,
            controls=controls,
            approach=measured["approach"],
            delta=measured["delta"],
            moment=measured["moment"],
            rotation=measured["rotation"],
            tilt=measured["tilt"],
            x=x,
            pressure=p,
            shear=q,
            normal_displacement=gap,
            tangential_displacement=slip,
            states=states,
            iterations=iterations,
            residuals=tuple(residuals),
            seconds=seconds,
            unknowns=state.x,
            resultant=resultant,
            errors=errors,
            exact=exact,
            layout=problem.layout,
            loads=dict(state.loads),
            increments=tuple(increments),
        )
        if checks is not None:  # the record's own checks, set before it leaves here: a second
            # record (attrs.evolve) would run every field's converter again, 9 us a step
            object.__setattr__(step, "checks", checks(step))
        return step

    def count(self, state: str) -> int:
        """Number of pairs in ``state`` ("separated", "stick" or "slip")."""
        return int(np.sum(self.states == STATE_NAMES.index(state)))

    @property
    def bulk(self) -> float:
        """The specimen's bulk stress sigma_B at the end of the step (MPa; 0 without one)."""
        return float(self.loads.get("bulk", 0.0)) if self.loads else 0.0

    def zones(self) -> StepZones:
        """Contact extent, stick zones and signed slip zones (from the pair states)."""
        return step_zones(self)


#: summary.json key of each estimate, beside the error key it estimates
ESTIMATE_KEYS = {k: "est" + k[1:] for k in ERROR_KEYS}


@attrs.frozen(eq=False)
class SimulationResult:
    """Results of every step and the run's timings (seconds).

    ``accuracy`` (set by :func:`fretbem.accuracy.modes.solve`) records the mesh mode, the pairs
    of every level solved, their time and, where no step has an estimate, the reason.
    """

    simulation: object
    steps: tuple[StepResult, ...]
    timings: dict[str, float]
    accuracy: AccuracyRecord | None = None

    def __repr__(self) -> str:
        return result_repr(self)

    def _repr_html_(self) -> str:
        return result_html(self)

    def __getitem__(self, name: str) -> StepResult:
        for step in self.steps:
            if step.name == name:
                return step
        raise KeyError(f"no step {name!r}; steps are {[s.name for s in self.steps]}")

    def describe(self) -> dict:
        """Scene facts for the summary: family, pairs, degrees of freedom."""
        pair = self.simulation.pair
        lower, upper = pair.lower.describe(), pair.upper.describe()
        return {
            "basis": lower.get("basis", upper.get("basis")),
            "degree": lower.get("degree", upper.get("degree")),
            "models": {"upper": upper.get("model"), "lower": lower.get("model")},
            "solver": type(self.simulation.solver).__name__,
            "pairs": int(pair.n_pairs),
            "dofs": int(pair.upper.dofs + pair.lower.dofs),
            "friction": getattr(self.simulation.law, "friction", None),
            "pairing": type(pair).__name__,
            # node to segment: one frame for all pairs or each its own (a slide along an arc)
            "frame": getattr(pair, "frame", None),
            "faces": {
                label: {
                    "basis": body.describe().get("basis"),
                    "degree": body.describe().get("degree"),
                    "nodes": int(body.contact_face(tag).n_nodes),
                }
                for label, (body, tag) in (
                    ("upper", (pair.upper, pair.upper_tag)),
                    ("lower", (pair.lower, pair.lower_tag)),
                )
            },
        }

    def table(self) -> str:
        """Per-step table of errors beside their estimates ("est"), iterations and times."""

        def fmt(value):
            return "   n/a" if value is None else f"{100 * value:6.3f}"

        width = max(4, *(len(s.name) for s in self.steps))
        lines = [
            f"{'step':<{width}}      P        Q   e_p max%     est  e_q max%     est  "
            "e_p L2%     est  e_q L2%     est  iters  stick  slip  time s",
        ]
        for s in self.steps:
            e, est = s.errors or {}, s.estimate or {}
            cells = "  ".join(f"{fmt(e.get(k))}  {fmt(est.get(k))}" for k in ERROR_KEYS)
            lines.append(
                f"{s.name:<{width}} {s.normal:7.2f} {s.tangential:8.2f}  {cells}  "
                f"{s.iterations:5d}  {s.count('stick'):5d} {s.count('slip'):5d}  {s.seconds:6.3f}"
            )
        t = self.timings
        lines.append(
            f"assembly {t['assembly']:.3f} s, factorisation {t['factorisation']:.3f} s, "
            f"condensation {t['condensation']:.3f} s, steps {t['steps']:.3f} s, "
            f"total {t['total']:.3f} s"
        )
        lines.append(self.accuracy_line())
        return "\n".join(lines)

    def accuracy_line(self) -> str:
        """One line: the mesh mode, the levels solved and where the estimate comes from."""
        record = self.accuracy
        if record is None:
            return "no estimate: one level solved (fretbem.accuracy.modes.solve adds the estimate)"
        levels = record.get("levels", [])
        pairs = ", ".join(str(n) for n in levels)
        seconds = record.get("seconds")
        time_text = f"; all levels {seconds:.3f} s" if seconds is not None else ""
        if record.get("estimate_reason"):
            source = f"no estimate: {record['estimate_reason']}"
        elif record.get("mesh") == "adaptive":
            source = "est from the last two adaptive levels (fretbem.accuracy.adaptive)"
        else:
            source = (
                f"est from the companion level of {levels[0]} pairs (uniform: the change "
                f"x {record.get('factor', float('nan')):.2f})"
            )
        mode = "adaptive" if record.get("mesh") == "adaptive" else "fixed"
        caution = f"\ncaution: {record['caution']}" if record.get("caution") else ""
        return f"{mode} mesh, levels {pairs} pairs{time_text}; {source}{caution}"

    def to_xarray(self):
        """The run as an :class:`xarray.Dataset`: dims step and pair, coords x and the step
        names, p, q, un, ut, slip, state, zones, errors, estimates and checks, with CF units
        (:func:`fretbem.views.run.run_dataset`)."""
        return run_dataset(self)

    def hertz(self) -> dict | None:
        """Hertz P, a and p0 of the run's closed form (None where no closed form applies)."""
        return hertz_numbers(self.simulation.reference)

    def theory_stick_zones(self) -> list:
        """Per step the closed form's stick zone (e - c, e + c), mm; None without theory."""
        return theory_stick_zones(self.simulation.reference, [s.tangential for s in self.steps])

    def summary(self) -> dict:
        """Per-step loads (sigma_B included), errors and estimates (None where they do not
        apply), zones beside theory, iterations, times, Hertz a and p0, and the accuracy
        record (mesh mode, levels, why no estimate)."""
        steps = []
        theory = self.theory_stick_zones()
        rotates = bool(getattr(self.simulation, "rotates", False))
        for s, zone in zip(self.steps, theory, strict=True):
            e, est = s.errors or {}, s.estimate or {}
            steps.append(
                {
                    "step": s.name,
                    "P": s.normal,
                    "Q": s.tangential,
                    "sigma_B": s.bulk,
                    **s.zones().as_dict(),
                    "theory_stick_zone": None if zone is None else list(zone),
                    **{k: e.get(k) for k in ERROR_KEYS},
                    **{ESTIMATE_KEYS[k]: est.get(k) for k in ERROR_KEYS},
                    "delta": s.delta,
                    "approach": s.approach,
                    "M": s.moment,
                    "theta": s.rotation,
                    "tilt": s.tilt,
                    "control": {
                        "normal": s.controls.normal,
                        "tangential": s.controls.tangential,
                        **({"rotation": s.controls.rotation} if rotates else {}),
                    },
                    "integral_p": s.resultant[0],
                    "integral_q": s.resultant[1],
                    "iterations": s.iterations,
                    "residuals": list(s.residuals),
                    "stick": s.count("stick"),
                    "slip": s.count("slip"),
                    "separated": s.count("separated"),
                    "seconds": s.seconds,
                }
            )
        accuracy = self.accuracy.as_dict() if self.accuracy is not None else {
            "mesh": "fixed", "levels": [int(self.steps[0].x.size)],
            "estimate_reason": "one level solved (fretbem.accuracy.modes.solve adds the estimate)",
        }  # fmt: skip
        return {
            "scene": self.describe(),
            "hertz": self.hertz(),
            "timings": dict(self.timings),
            "accuracy": accuracy,
            "steps": steps,
        }
