"""A wear history: a load cycle repeated over many cycles, the faces wearing as it goes.

``run_wear`` solves the simulation's first steps (the pressing before the cycles) once,
then alternates a simulated cycle on the current worn profile
(:func:`~fretbem.wear.cycle.simulate_cycle`) with a jump of Delta N cycles
(:class:`~fretbem.wear.jump.JumpControl`), landing exactly on every requested N where it
keeps a :class:`WearSnapshot`. After a jump the state at the end of the last cycle is first
re-equilibrated on the new profile (its last step's loads, one increment, no wear counted):
the gap changed under a contact that may be sliding, and starting the next cycle's
reversal from the old equilibrium is what a Newton solver does not survive. Nothing is
written; :mod:`fretbem.output.wear` writes.
"""

from __future__ import annotations

import re
import time
from collections.abc import Mapping

import attrs
import numpy as np

from fretbem.contact.law import ContactState
from fretbem.contact.node_to_segment import FRAMES, NodeToSegmentPair
from fretbem.results import SimulationResult
from fretbem.simulation import BlockTippingError, LoadStep, Simulation, run, run_resources
from fretbem.sliding import solve_sliding
from fretbem.solvers.newton import SolverConvergenceError
from fretbem.validators import count_field, whole_number

from .cycle import CycleWear, simulate_cycle
from .jump import Jump, JumpControl, extrapolate
from .law import ScarEdgeError, WearInputError, WearLaw
from .profile import BODIES, WornPair, WornProfile
from .slide import Track, check_pair, simulate_sliding_cycle

#: the step names of a waveform history ([load.cycle]): c<cycle>.<increment>
WAVEFORM = re.compile(r"c(\d+)\.(\d+)")

__all__ = ["WearResult", "WearSimulation", "WearSnapshot", "run_wear", "worn_simulation"]


def _laws(value) -> dict:
    return dict(value)


def _outputs(value) -> tuple[int, ...]:
    """The snapshot cycles: whole numbers >= 0 (no True, no "100", no 2.5)."""
    fix = "give the cycle numbers N at which to keep the worn profile, e.g. [1000, 10000]"
    return tuple(
        whole_number(f"WearSimulation.outputs[{k}]", n, low=0, fix=fix, error=WearInputError)
        for k, n in enumerate(value)
    )


@attrs.frozen(eq=False)
class WearSimulation:
    """A simulation whose load cycle is repeated ``cycles`` times while both faces wear.

    Attributes
    ----------
    simulation : Simulation
        The contact, solver and law; its steps before ``cycle`` are solved once (the
        pressing), then ``cycle`` is repeated.
    laws : mapping "upper"/"lower" -> WearLaw
        Each body's wear law (coefficient 0: the body does not wear).
    cycles : int
        Total number of load cycles N.
    cycle : tuple of str
        Names of the simulation's steps forming one cycle (default: every step after the
        first).
    control : JumpControl
    outputs : tuple of int
        The N at which snapshots are kept (0 and ``cycles`` are always kept).
    sliding : bool
        Finite sliding (``[contact] sliding``): the pairing follows the pad as it slides
        and each face wears at its own material points (:mod:`fretbem.wear.slide`); the
        pair must be a node-to-segment one. False: the pairs stay where they are (small
        slip).
    frame : str
        With ``sliding`` along an arc, the pair frame (``[contact] frame``): ``"local"``
        (default: each pair its own) or ``"shared"`` (the pad's turned frame;
        :func:`~fretbem.sliding.slide.run_sliding`). A straight track's pairs share one
        frame either way.
    """

    simulation: Simulation
    laws: Mapping[str, WearLaw] = attrs.field(converter=_laws)
    cycles: int = attrs.field(
        converter=count_field("give the total number of load cycles N", error=WearInputError)
    )
    cycle: tuple[str, ...] = attrs.field(default=(), converter=tuple)
    control: JumpControl = attrs.field(factory=JumpControl)
    outputs: tuple[int, ...] = attrs.field(default=(), converter=_outputs)
    sliding: bool = attrs.field(default=False, validator=attrs.validators.instance_of(bool))
    frame: str = "local"

    def __attrs_post_init__(self) -> None:
        if set(self.laws) != set(BODIES):
            raise WearInputError(
                f"give a wear law for each body, 'upper' (pad) and 'lower' (specimen); got "
                f"{sorted(self.laws)}"
            )
        for body, law in self.laws.items():
            if not isinstance(law, WearLaw):
                raise WearInputError(f"the {body} body's wear law is not a WearLaw: {law!r}")
        if self.cycles < 1:
            raise WearInputError(f"[wear] cycles must be >= 1, got {self.cycles}")
        bad = [n for n in self.outputs if not 0 <= n <= self.cycles]
        if bad:
            raise WearInputError(
                f"[wear] output asks for N = {bad[0]}, outside 0..cycles = {self.cycles}"
            )
        names = [s.name for s in self.simulation.steps]
        unknown = [c for c in self.cycle if c not in names]
        if unknown:
            raise WearInputError(
                f"[wear] cycle names step {unknown[0]!r}, which the load history does not "
                f"have (its steps are {names})"
            )
        if self.frame not in FRAMES:
            raise WearInputError(
                f"the wear history's pair frame must be 'local' (each pair its own along an "
                f"arc) or 'shared' (the pad's turned frame), got {self.frame!r}"
            )
        if self.frame != "local" and not self.sliding:
            raise WearInputError(
                f"frame = {self.frame!r} chooses the pair frame of finite sliding along an arc, "
                "but sliding is off (the pairs stay where they are); give sliding=True or "
                "leave frame out"
            )
        if self.sliding and self.control.scheme != "explicit":
            raise WearInputError(
                f"[wear] scheme = {self.control.scheme!r} is not available with finite "
                "sliding ([contact] sliding = true): its linearisation ties each pair's depth "
                "to its own pressure, which sliding spreads along the track; use scheme = "
                "'explicit'"
            )
        if self.sliding and isinstance(self.simulation.pair, NodeToSegmentPair):
            check_pair(self.simulation.pair)  # before the sliding run, not after it
        if len(self.simulation.steps) < 2 and not self.cycle:
            raise WearInputError(
                "a wear history needs a load cycle after the pressing step: give [load] "
                "steps after the first (e.g. Q up, down and back) or name them in [wear] cycle"
            )

    @property
    def cycle_steps(self) -> tuple[LoadStep, ...]:
        """The steps of one cycle: ``cycle``'s, else those of the first load cycle of a
        waveform history (steps named ``c1.<increment>``), else every step after the first."""
        steps = self.simulation.steps
        if not self.cycle:
            waveform = [s for s in steps[1:] if WAVEFORM.fullmatch(s.name)]
            if waveform and len(waveform) == len(steps) - 1:
                return tuple(s for s in waveform if int(WAVEFORM.fullmatch(s.name).group(1)) == 1)
            return tuple(steps[1:])
        by_name = {s.name: s for s in steps}
        return tuple(by_name[name] for name in self.cycle)

    @property
    def preload_steps(self) -> tuple[LoadStep, ...]:
        """The steps solved once before the cycles: those before the cycle's first."""
        steps = self.simulation.steps
        first = self.cycle_steps[0]
        return tuple(steps[: next(k for k, s in enumerate(steps) if s is first)])

    @property
    def snapshot_cycles(self) -> tuple[int, ...]:
        """Every N with a snapshot, ascending."""
        return tuple(sorted({0, self.cycles, *self.outputs}))


@attrs.frozen(eq=False)
class WearSnapshot:
    """The worn state at N cycles and the cycle solved on it.

    Attributes
    ----------
    profile : WornProfile
        Wear depths at N.
    pressure, shear : ndarray (n_steps, n)
        p and q at the end of each cycle step, solved on the profile at N.
    energy : float
        Dissipated energy summed over the N cycles (N mm per mm of thickness).
    work : float
        Archard work sum(w p |ds|) over the N cycles (N mm per mm).
    positions : ndarray (n_steps, n) or None
        With finite sliding, where the pairs of ``pressure`` and ``shear`` were along the
        specimen at each step's end; None: at ``profile.x``.
    moment, rotation, tilt : ndarray (n_steps,) or None
        A rotating pad block's M (N mm/mm), the actuator's rotation theta and the block's
        tilt (rad) at the end of each cycle step at N; None: the block does not rotate.
    """

    profile: WornProfile
    pressure: np.ndarray
    shear: np.ndarray
    energy: float
    work: float
    positions: np.ndarray | None = None
    moment: np.ndarray | None = None
    rotation: np.ndarray | None = None
    tilt: np.ndarray | None = None

    def pair_x(self, step: int = 0) -> np.ndarray:
        """The positions (mm along the specimen) of the pairs at the end of cycle step
        ``step``."""
        return self.profile.x if self.positions is None else self.positions[step]

    @property
    def cycles(self) -> int:
        """N."""
        return self.profile.cycles


@attrs.frozen(eq=False)
class WearResult:
    """A wear history: snapshots at the requested N and every jump taken.

    Attributes
    ----------
    wear : WearSimulation
    snapshots : tuple of WearSnapshot
        At every N of ``wear.snapshot_cycles``.
    jumps : tuple of (int, Jump)
        The N each jump started from and the jump.
    simulated : int
        Cycles actually solved.
    seconds : float
    """

    wear: WearSimulation
    snapshots: tuple[WearSnapshot, ...]
    jumps: tuple[tuple[int, Jump], ...]
    simulated: int
    seconds: float

    def snapshot(self, cycles: int) -> WearSnapshot:
        """The snapshot at N = ``cycles`` (one of ``wear.snapshot_cycles``)."""
        for snap in self.snapshots:
            if snap.cycles == cycles:
                return snap
        raise WearInputError(
            f"no wear snapshot at N = {cycles}; the snapshots are at "
            f"{[s.cycles for s in self.snapshots]} (add N to [wear] output)"
        )

    @property
    def final(self) -> WearSnapshot:
        """The snapshot at the last cycle."""
        return self.snapshots[-1]

    def at(self, cycles: int) -> SimulationResult:
        """The scene's whole load history solved on the profile at N = ``cycles``: a
        SimulationResult for the stresses and the fatigue assessment after wear (with
        finite sliding, run re-pairing as the pad slides, each face's wear carried along)."""
        profile = self.snapshot(cycles).profile
        simulation = worn_simulation(
            self.wear.simulation, profile, self.wear.sliding, self.wear.frame
        )
        if self.wear.sliding:
            return solve_sliding(simulation, say=lambda _: None, frame=self.wear.frame)
        return run(simulation)


#: how many times a cycle whose Newton iteration fails is retried with doubled increments
RETRIES = 2


class _Pairs:
    """The wear history's contact on fixed pairs: the base pair's condensation, the gap
    offset by the profile (:class:`~fretbem.wear.profile.WornPair`)."""

    def __init__(self, wear: WearSimulation) -> None:
        self.simulation = wear.simulation
        self.base = wear.simulation.pair
        self.problem = self.initial = wear.simulation.prepare()

    def start(self) -> ContactState:
        return ContactState.initial(self.problem)

    def unworn(self) -> WornProfile:
        return WornProfile.unworn(self.problem)

    def wear(self, profile: WornProfile) -> None:
        # the worn pair's pad block turns as the first's did (the simulation's own pivot)
        self.problem = self.simulation.condense(WornPair.of(self.base, profile.offset))

    def step(self, state: ContactState, load: LoadStep) -> ContactState:
        return self.simulation.step(self.problem, state, load)[0]

    def cycle(self, state, steps, laws, profile) -> CycleWear:
        return simulate_cycle(self.simulation, self.problem, state, steps, laws)


class _Sliding:
    """The wear history's contact with finite sliding: the pairing follows the pad
    (:class:`~fretbem.wear.slide.Track`), each face's wear on the track's grid."""

    def __init__(self, wear: WearSimulation) -> None:
        self.track = Track.start(wear.simulation, wear.frame)
        self.initial = self.track.problem

    @property
    def problem(self):
        return self.track.problem

    def start(self) -> ContactState:
        return ContactState.initial(self.problem)

    def unworn(self) -> WornProfile:
        return self.track.unworn()

    def wear(self, profile: WornProfile) -> None:
        self.track = self.track.worn(profile)

    def step(self, state: ContactState, load: LoadStep) -> ContactState:
        self.track, state, _ = self.track.step(state, load)
        return state

    def cycle(self, state, steps, laws, profile) -> CycleWear:
        cycle, self.track = simulate_sliding_cycle(self.track, state, steps, laws, profile)
        return cycle


def _cycle(contact, state: ContactState, wear: WearSimulation, n: int, profile: WornProfile):
    """One simulated cycle; a cycle whose solver fails is solved again with its steps'
    increments doubled (a sliding contact whose pairs all reach the cone together at a
    reversal can need finer increments than the unworn contact did); a rotating block that
    tips is refused at once."""
    steps = wear.cycle_steps
    for attempt in range(RETRIES + 1):
        try:
            return contact.cycle(state, steps, wear.laws, profile)
        except BlockTippingError:  # the moment's answer, not the increments' size
            raise
        except SolverConvergenceError as error:
            if attempt == RETRIES:
                raise SolverConvergenceError(
                    f"the wear cycle at N = {n} did not converge even with "
                    f"{2**RETRIES} times the increments ({error}); give more [wear] increments "
                    "or a smaller relative_change"
                ) from None
            steps = tuple(attrs.evolve(s, increments=2 * s.increments) for s in steps)
    raise AssertionError("unreachable")  # pragma: no cover


def _check_edges(pressure: np.ndarray, cycles: int, x: np.ndarray) -> None:
    """The contact must stay inside the candidate zone as the scar widens."""
    edge = pressure[:, [0, -1]]
    if np.any(edge > 0):
        raise ScarEdgeError(
            f"the worn contact reached the end pairs of the candidate zone (x = {x[0]:.4g}, "
            f"{x[-1]:.4g} mm, p up to {edge.max():.4g} MPa) after {cycles} wear cycles, so "
            "the scar may be wider than the zone; enlarge [contact] zone (or zone_width) "
            "until the end pairs stay separated, or wear fewer cycles",
            float(edge.max()),
        )


def _relief(problem, pressure: np.ndarray) -> float:
    """Spread of the unworn initial gap over the pairs in contact at any step end (mm)."""
    touching = np.any(pressure > 0, axis=0)
    return float(np.ptp(problem.gap[touching])) if touching.any() else 0.0


def worn_simulation(
    simulation: Simulation, profile: WornProfile, sliding: bool = False, frame: str = "local"
):
    """``simulation`` on the worn contact: its pair's gap offset by the profile's depths
    (the closest pairs brought to touch when every step imposes P, see WornPair); with
    ``sliding`` a :class:`~fretbem.wear.track.WornTrackPair` carrying each face's wear at
    its material points, to run with finite sliding (``frame``: its pair frame along an
    arc)."""
    touching = all(getattr(s, "approach", None) is None for s in simulation.steps)
    simulation = simulation.pinned()  # a rotating block turns where the unworn pad's did
    if sliding:
        pair = Track.start(simulation, frame).pair.rewear(profile.upper, profile.lower)
        pair = pair.touching() if touching else pair
    else:
        pair = WornPair.of(simulation.pair, profile.offset, touching=touching)
    return attrs.evolve(simulation, pair=pair, name=f"{simulation.name} at N = {profile.cycles}")


def run_wear(wear: WearSimulation, *, progress=None) -> WearResult:
    """Solve the wear history: pressing, then simulated cycles and jumps up to ``cycles``.

    ``progress(N, cycles)`` is called after each jump.
    """
    start = time.perf_counter()
    with run_resources(wear.simulation):
        return _run_wear(wear, progress, start)


def _run_wear(wear: WearSimulation, progress, start: float) -> WearResult:
    """:func:`run_wear` in the run's resource block."""
    contact = _Sliding(wear) if wear.sliding else _Pairs(wear)
    state = contact.start()
    for load in wear.preload_steps:
        state = contact.step(state, load)
    profile = contact.unworn()
    targets = list(wear.snapshot_cycles)
    energy = work = 0.0
    snapshots, jumps, simulated = [], [], 0
    n = 0
    while True:
        if n:  # the end of the last cycle, re-equilibrated on the new profile
            contact.wear(profile)
            state = contact.step(state, attrs.evolve(wear.cycle_steps[-1], increments=1))
        cycle = _cycle(contact, state, wear, n, profile)
        simulated += 1
        where = profile.x if cycle.positions is None else cycle.positions[0]
        _check_edges(cycle.pressure, n, where)
        if n == targets[0]:
            targets.pop(0)
            snapshots.append(WearSnapshot(profile, cycle.pressure, cycle.shear, energy, work,
                                          cycle.positions, cycle.moment, cycle.rotation,
                                          cycle.tilt))  # fmt: skip
        if n >= wear.cycles:
            break
        if n == 0:
            relief = _relief(contact.initial, cycle.pressure)
        worn = contact.problem
        jump = wear.control.jump(worn, cycle, targets[0] - n, first=n == 0, relief=relief)
        added, cycles = extrapolate(worn, cycle, jump.cycles, wear.control.scheme, profile.weights)
        if cycles < jump.cycles:
            jump = attrs.evolve(jump, cycles=cycles, limit="positivity")
        jumps.append((n, jump))
        n += cycles
        profile = profile.worn(n, added.depth["upper"], added.depth["lower"])
        energy, work = energy + added.energy, work + added.work
        state = cycle.state
        if progress is not None:
            progress(n, wear.cycles)
    return WearResult(wear, tuple(snapshots), tuple(jumps), simulated,
                      time.perf_counter() - start)  # fmt: skip


def simulate(simulation: Simulation, laws: Mapping[str, WearLaw], cycles: int,
             **options) -> WearResult:  # fmt: skip
    """Shorthand: ``run_wear(WearSimulation(simulation, laws, cycles, **options))``."""
    return run_wear(WearSimulation(simulation, laws, cycles, **options))
