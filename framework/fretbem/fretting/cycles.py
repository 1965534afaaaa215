"""Per increment and per cycle results of a fretting history: loops, slip, energy, regime.

Every increment of a run is kept (:attr:`fretbem.results.StepResult.increments`): the
block's Q, delta and P, and per pair the slip s (relative tangential displacement, upper
minus lower) and the tractions. Over one cycle (the steps tagged with that cycle, started
from the increment before it, so the loop closes):

- the Q-delta loop, its amplitudes Q* and delta* (half the ranges) and its area;
- per pair the slip amplitude (half the range of s) and the dissipated energy density
  w = sum over increments of q_mid ds (trapezoidal in each increment);
- the dissipated energy E_d = integral of w (the pair weights of the face), the energy
  ratio A = E_d / (4 delta* Q*) and the regime: ``gross slip`` when some increment has no
  sticking pair in contact, ``partial slip`` when some pair slips, else ``stick``.

delta is the pad's loading block against the specimen's held end (a 2D displacement needs
a datum); s, its amplitude and the energy do not depend on it. docs/explanation/fretting.rst
has the theory and the 2D transition value of A.
"""

from __future__ import annotations

import math

import attrs
import numpy as np

from fretbem.contact.control import frame
from fretbem.verification.fretting import onset_energy

STICK, SLIP = 1, 2
#: the regimes, in order of growing slip
REGIMES = ("stick", "partial slip", "gross slip")


def _frozen(values) -> np.ndarray:
    out = np.array(values, dtype=float)
    out.setflags(write=False)
    return out


@attrs.frozen(eq=False)
class CycleResult:
    """One load cycle.

    Attributes
    ----------
    cycle : int
    increments : ndarray of int
        Global increment numbers of the loop (the start point first).
    tangential, delta, normal : ndarray
        Q (N/mm), delta (mm) and P (N/mm) along the loop.
    x : ndarray
        Pair positions (mm).
    slip_amplitude : ndarray
        Half the range of the slip s(x) over the increments of the cycle where the pair is
        in contact, per pair (mm; 0 for a pair never in contact).
    energy_density : ndarray
        Dissipated energy per unit area of the face per pair over the cycle (N/mm = mJ/mm^2).
    dissipated_energy : float
        E_d, integral of the energy density (N mm/mm = mJ per mm of thickness).
    loop_area : float
        The area of the Q-delta loop (same unit): E_d again, through the block; with the
        block's rotation, the work of its moment M d(theta) over the cycle is added.
    delta_amplitude, tangential_amplitude : float
        delta* and Q*.
    energy_ratio : float
        A = E_d / (4 delta* Q*) (NaN when delta* Q* = 0).
    regime : str
        ``stick``, ``partial slip`` or ``gross slip``.
    caution : str or None
        Set when the slip range exceeds the pair spacing: the node-to-node pairing assumes
        small sliding, so the result is then beyond what it models.
    """

    cycle: int
    increments: np.ndarray
    tangential: np.ndarray = attrs.field(converter=_frozen)
    delta: np.ndarray = attrs.field(converter=_frozen)
    normal: np.ndarray = attrs.field(converter=_frozen)
    x: np.ndarray = attrs.field(converter=_frozen)
    slip_amplitude: np.ndarray = attrs.field(converter=_frozen)
    energy_density: np.ndarray = attrs.field(converter=_frozen)
    dissipated_energy: float
    loop_area: float
    delta_amplitude: float
    tangential_amplitude: float
    energy_ratio: float
    regime: str
    caution: str | None = None

    def as_dict(self) -> dict:
        """summary.json's entry of this cycle."""
        return {
            "cycle": self.cycle,
            "dissipated_energy": self.dissipated_energy,
            "loop_area": self.loop_area,
            "delta_amplitude": self.delta_amplitude,
            "Q_amplitude": self.tangential_amplitude,
            "energy_ratio": self.energy_ratio,
            "regime": self.regime,
            "slip_amplitude_max": float(np.max(self.slip_amplitude, initial=0.0)),
            "caution": self.caution,
        }


@attrs.frozen(eq=False)
class FrettingAnalysis:
    """Every increment of a run and its cycles.

    Attributes
    ----------
    increment, cycle : ndarray of int
        Global increment number (1, 2, ...) and cycle (0: outside any cycle).
    step : tuple of str
        The step of each increment.
    tangential, delta, normal : ndarray
        Q, delta, P per increment.
    moment, rotation : ndarray
        M (N mm/mm, about the rig's pivot; NaN where the pad's model gives none) and the
        actuator's rotation theta (rad) per increment.
    weights : ndarray
        Face length per pair (mm): the integral of a field over the face is weights @ field.
    cycles : tuple of CycleResult
    transition_ratio : float or None
        The energy ratio at the partial / gross slip transition of this scene (None where no
        Hertz closed form applies); see docs/explanation/fretting.rst.
    """

    increment: np.ndarray
    cycle: np.ndarray
    step: tuple[str, ...]
    tangential: np.ndarray = attrs.field(converter=_frozen)
    delta: np.ndarray = attrs.field(converter=_frozen)
    normal: np.ndarray = attrs.field(converter=_frozen)
    weights: np.ndarray = attrs.field(converter=_frozen)
    cycles: tuple[CycleResult, ...] = ()
    transition_ratio: float | None = None
    moment: np.ndarray = attrs.field(default=(), converter=_frozen)
    rotation: np.ndarray = attrs.field(default=(), converter=_frozen)

    def table(self) -> str:
        """One line per cycle: Q*, delta*, E_d, A and the regime (the command line's report)."""
        lines = [
            "cycle        Q*       delta*          E_d        A  regime",
            *(
                f"{c.cycle:5d} {c.tangential_amplitude:9.4g} {c.delta_amplitude:12.4g} "
                f"{c.dissipated_energy:12.4g} {c.energy_ratio:8.4g}  {c.regime}"
                + (" (caution: sliding beyond the pair spacing)" if c.caution else "")
                for c in self.cycles
            ),
        ]
        if self.transition_ratio is not None:
            lines.append(
                f"Q* N/mm, delta* mm (pad block against the specimen's held end), E_d N mm/mm; "
                f"gross slip sets in at A = {self.transition_ratio:.4g} in this scene"
            )
        return "\n".join(lines)

    def summary(self) -> dict:
        """summary.json's ``fretting`` table: the transition ratio and every cycle."""
        return {
            "transition_ratio": self.transition_ratio,
            "cycles": [c.as_dict() for c in self.cycles],
        }


def pair_weights(problem) -> np.ndarray:
    """Face length per pair: the contact force on the lower body per unit q, along t."""
    _, t = frame(problem)
    return t @ problem.lower_force_map[:, problem.layout.shear]


def _loop_area(q: np.ndarray, d: np.ndarray, m=None, theta=None) -> float:
    """The block's work over the loop: Q d(delta), plus M d(theta) when the block turns."""
    area = float(np.sum(0.5 * (q[1:] + q[:-1]) * np.diff(d)))
    if theta is not None and np.any(np.diff(theta) != 0.0):
        area += float(np.sum(0.5 * (m[1:] + m[:-1]) * np.diff(theta)))
    return area


def _regime(states: np.ndarray) -> str:
    contact = states != 0
    no_stick = np.any(contact, axis=1) & ~np.any(states == STICK, axis=1)
    if np.any(no_stick):
        return "gross slip"
    if np.any(states == SLIP):
        return "partial slip"
    return "stick"


def analyse(result) -> FrettingAnalysis:
    """Loops, slip amplitude, energy and regime of every cycle of ``result`` (a
    SimulationResult whose steps carry their increments)."""
    simulation = result.simulation
    problem = simulation.prepare()
    weights = pair_weights(problem)
    records, cycles, steps = [], [], []
    for load, step in zip(simulation.steps, result.steps, strict=True):
        for record in step.increments:
            records.append(record)
            cycles.append(load.cycle)
            steps.append(step.name)
    cycle = np.array(cycles, dtype=int)
    q = np.array([r.tangential for r in records])
    d = np.array([r.delta for r in records])
    p = np.array([r.normal for r in records])
    m = np.array([getattr(r, "moment", math.nan) for r in records])
    theta = np.array([getattr(r, "rotation", 0.0) for r in records])
    x = np.asarray(result.steps[0].x)
    found = []
    repaired = any(s.pair is not None for s in result.steps)  # finite sliding follows the pad
    for number in sorted(set(cycle.tolist()) - {0}):
        members = np.flatnonzero(cycle == number)
        start = members[0] - 1
        loop = np.concatenate([[start], members]) if start >= 0 else members
        found.append(_cycle(number, loop, records, q, d, p, x, weights, repaired, (m, theta)))
    return FrettingAnalysis(
        increment=np.arange(1, len(records) + 1),
        cycle=cycle,
        step=tuple(steps),
        tangential=q,
        delta=d,
        normal=p,
        weights=weights,
        cycles=tuple(found),
        transition_ratio=transition_ratio(simulation, problem, result),
        moment=m,
        rotation=theta,
    )


def _cycle(number, loop, records, q, d, p, x, weights, repaired=False, turns=None) -> CycleResult:
    slip = np.array([records[i].slip for i in loop])
    shear = np.array([records[i].shear for i in loop])
    every = np.array([records[i].states for i in loop])
    states = every[1:]
    # slip is relative tangential motion of pairs in contact: a separated pair's motion is not
    touching = np.where(every != 0, slip, np.nan)
    never = ~np.any(every != 0, axis=0)
    touching[:, never] = 0.0
    amplitude = 0.5 * (np.nanmax(touching, axis=0) - np.nanmin(touching, axis=0))
    density = np.sum(0.5 * (shear[1:] + shear[:-1]) * np.diff(slip, axis=0), axis=0)
    energy = float(weights @ density)
    d_star = 0.5 * float(np.ptp(d[loop]))
    q_star = 0.5 * float(np.ptp(q[loop]))
    scale = 4.0 * d_star * q_star
    spacing = float(np.median(np.diff(np.sort(x)))) if len(x) > 1 else math.inf
    slip_range = 2.0 * float(np.max(amplitude, initial=0.0))
    caution = None
    if slip_range > spacing and not repaired:
        caution = (
            f"the slip range {slip_range:.3g} mm exceeds the pair spacing {spacing:.3g} mm; "
            "node-to-node pairs assume sliding small against it, so this cycle is beyond "
            "what the pairing models"
        )
    return CycleResult(
        cycle=number,
        increments=loop + 1,
        tangential=q[loop],
        delta=d[loop],
        normal=p[loop],
        x=x,
        slip_amplitude=amplitude,
        energy_density=density,
        dissipated_energy=energy,
        loop_area=_loop_area(
            q[loop], d[loop], *((turns[0][loop], turns[1][loop]) if turns else (None, None))
        ),
        delta_amplitude=d_star,
        tangential_amplitude=q_star,
        energy_ratio=energy / scale if scale > 0 else math.nan,
        regime=_regime(states),
        caution=caution,
    )


def onset_displacement(problem, press, friction: float) -> float:
    """delta at the onset of gross slip from the pressed step ``press`` (a StepResult):
    every pair at q = f p, the centre pair still at its slip after the press.

    The model's own compliance between the block and the datum, so it holds for any body
    model: the block displacement that makes the centre pair's slip increment vanish when
    the shear is f p everywhere (p unchanged: exact for similar bodies)."""
    layout = problem.layout
    x = np.array(press.unknowns, dtype=float)
    p = x[layout.pressure]
    x[layout.shear] = friction * p
    _, t = frame(problem)
    unit = np.zeros(layout.size)
    unit[layout.block("upper")] = t
    centre = int(np.argmax(p))
    _, tangential_base, _ = problem.bases(problem.amplitudes(press.loads))
    row = problem.tangential_map[centre]
    slip = press.tangential_displacement[centre]
    shift = (slip - tangential_base[centre] - row @ x) / (row @ unit)
    return float(shift)


def transition_ratio(simulation, problem, result) -> float | None:
    """A at the partial / gross slip transition: W(c = 0) / (4 f P delta_t), with
    W(0) = 2 f^2 P^2 / (pi E*) (the energy per cycle as c -> 0) and delta_t the onset
    displacement of this model (:func:`onset_displacement`, plus the rig springs' travel
    f P / k_t); None without a Hertz closed form."""
    reference = simulation.reference
    friction = getattr(simulation.law, "friction", None)
    if reference is None or friction is None:
        return None
    hertz = reference.hertz
    press = result.steps[0]
    load = press.normal
    onset = onset_displacement(problem, press, friction)
    if not onset > 0:
        return None
    rig = getattr(simulation, "rig", None)
    if rig is not None:  # the actuator travels the springs' f P / k_t further
        onset += friction * load * rig.compliances[1]
    energy = onset_energy(attrs.evolve(hertz, load=load), friction)
    return energy / (4.0 * friction * load * onset)
