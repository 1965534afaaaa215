"""A cyclic history as a waveform: amplitude, cycles, increments per cycle, sine or triangle.

:meth:`Waveform.steps` expands it into load steps, one per increment (every increment is
then a step of the results), after a first step that presses the bodies together. The
tangential drive is a force Q or a displacement delta of the pad's block; P and the bulk
stress may cycle too, in or out of phase with it.
"""

from __future__ import annotations

import attrs
import numpy as np

from fretbem.errors import InputError
from fretbem.simulation import LoadStep
from fretbem.validators import number_field, real_number, whole_number

#: the waveform shapes: value at the cycle fraction t (0 at t = 0, +1 at 1/4, -1 at 3/4)
SHAPES = ("sine", "triangle")
#: name of the first step (the normal load)
PRESS = "press"
#: most increments of a history (cycles x increments per cycle): every increment is a step
#: of the results (about 10 kB each at 61 pairs), and 10^5 of them take minutes to solve
MAX_INCREMENTS = 100_000


class WaveformError(InputError):
    """A waveform that cannot make a load history."""


def shape_value(shape: str, t) -> np.ndarray:
    """The unit waveform at cycle fractions ``t`` (period 1, +1 at 1/4, -1 at 3/4)."""
    t = np.asarray(t, dtype=float)
    if shape == "sine":
        return np.sin(2.0 * np.pi * t)
    phase = np.mod(t + 0.25, 1.0)  # triangle: -1 at phase 0, +1 at phase 1/2
    return 1.0 - 4.0 * np.abs(phase - 0.5)


def _check_choice(name: str, options: tuple[str, ...]):
    def check(instance, attribute, value) -> None:
        if value not in options:
            raise WaveformError(f"Waveform.{name} must be one of {list(options)}, got {value!r}")

    return check


def _whole(minimum: int):
    """Converter of a count: a whole number >= ``minimum`` (numpy's too; no True, no "4")."""

    def convert(value, field) -> int:
        fix = "give it as a whole number (no quotes)"
        where = f"Waveform.{field.name}"
        return whole_number(where, value, low=minimum, fix=fix, error=WaveformError)

    return attrs.Converter(convert, takes_field=True)


def _per_cycle(instance, attribute, value) -> None:
    if value % 4:
        raise WaveformError(
            f"Waveform.increments (per cycle) must be a multiple of 4 so the increments land "
            f"on the peaks (+amplitude at 1/4, -amplitude at 3/4 of the cycle), got {value}; "
            f"use e.g. {4 * max(1, round(value / 4))}"
        )


def _number(what: str, fix: str):
    return number_field(what, fix, error=WaveformError)


#: the moment fields of a waveform: what each is (its unit) and what to give instead
MOMENT_FIELDS = {
    "moment": (
        "N mm/mm, the mean moment on the pad's block",
        "give the mean in N mm/mm, or None for no mean moment",
    ),
    "moment_amplitude": ("N mm/mm", "give the amplitude in N mm/mm, or 0 for a steady moment"),
    "moment_phase": ("degrees", "give the phase of M against the drive in degrees, or 0"),
}


def _moment_value(value, field) -> float | None:
    """A moment field: a finite number (None too for the mean); no True, no "1.0"."""
    if value is None and field.name == "moment":
        return None
    what, fix = MOMENT_FIELDS[field.name]
    return real_number(f"Waveform.{field.name}", value, what=what, fix=fix, error=WaveformError)


@attrs.frozen
class Waveform:
    """A fully reversed tangential cycle, repeated, with P and bulk stress cycling along.

    Attributes
    ----------
    amplitude : float
        Q* (N/mm, force control) or delta* (mm, displacement control), > 0.
    normal : float
        Mean normal load P (N/mm, > 0).
    control : str
        ``"displacement"`` (delta imposed) or ``"force"`` (Q imposed).
    cycles : int
        Number of cycles (>= 1).
    increments : int
        Increments per cycle, a multiple of 4.
    shape : str
        ``"sine"`` or ``"triangle"``.
    normal_amplitude, normal_phase : float
        P(t) = P + P_a w(t + phase / 360): a cyclic normal load (phase in degrees).
    bulk, bulk_amplitude, bulk_phase : float
        The bulk stress sigma_B (MPa) the same way; 0 leaves it out.
    moment, moment_amplitude, moment_phase : float or None, float, float
        The moment M (N mm/mm) on the pad's block the same way (:mod:`fretbem.contact.rotation`);
        None (the default) with no amplitude leaves the block's rotation as the rig holds it.
    """

    amplitude: float = attrs.field(
        converter=_number("Q* in N/mm or delta* in mm", "give the drive's amplitude, > 0")
    )
    normal: float = attrs.field(converter=_number("the mean P, N/mm", "give the mean P in N/mm"))
    control: str = attrs.field(
        default="displacement", validator=_check_choice("control", ("force", "displacement"))
    )
    cycles: int = attrs.field(default=1, converter=_whole(1))
    increments: int = attrs.field(default=40, converter=_whole(4), validator=_per_cycle)
    shape: str = attrs.field(default="sine", validator=_check_choice("shape", SHAPES))
    normal_amplitude: float = attrs.field(
        default=0.0, converter=_number("N/mm", "give P's amplitude in N/mm, or 0 for a steady P")
    )
    normal_phase: float = attrs.field(
        default=0.0, converter=_number("degrees", "give the phase of P against the drive, or 0")
    )
    bulk: float = attrs.field(
        default=0.0, converter=_number("the mean bulk stress, MPa", "give it in MPa, or 0")
    )
    bulk_amplitude: float = attrs.field(
        default=0.0, converter=_number("MPa", "give the bulk stress amplitude in MPa, or 0")
    )
    bulk_phase: float = attrs.field(
        default=0.0,
        converter=_number("degrees", "give the phase of the bulk stress against the drive, or 0"),
    )
    moment: float | None = attrs.field(
        default=None, converter=attrs.Converter(_moment_value, takes_field=True)
    )
    moment_amplitude: float = attrs.field(
        default=0.0, converter=attrs.Converter(_moment_value, takes_field=True)
    )
    moment_phase: float = attrs.field(
        default=0.0, converter=attrs.Converter(_moment_value, takes_field=True)
    )

    def __attrs_post_init__(self) -> None:
        if not self.amplitude > 0:
            raise WaveformError(f"Waveform.amplitude must be > 0, got {self.amplitude}")
        if not self.normal > 0:
            raise WaveformError(f"Waveform.normal (the mean P) must be > 0, got {self.normal}")
        if self.cycles * self.increments > MAX_INCREMENTS:
            raise WaveformError(
                f"Waveform.cycles x increments = {self.cycles} x {self.increments} = "
                f"{self.cycles * self.increments} increments, more than {MAX_INCREMENTS:,} "
                "(each is a step of the results); simulate fewer cycles (the loops repeat "
                "from the second cycle on) or fewer increments per cycle"
            )
        if not abs(self.normal_amplitude) < self.normal:
            raise WaveformError(
                f"Waveform.normal_amplitude |{self.normal_amplitude}| must stay below the mean "
                f"P = {self.normal} so the bodies stay pressed together"
            )

    @property
    def has_moment(self) -> bool:
        """Whether the history drives the pad block's moment."""
        return self.moment is not None or self.moment_amplitude != 0.0

    @property
    def has_bulk(self) -> bool:
        """Whether the history drives the bulk stress."""
        return self.bulk != 0.0 or self.bulk_amplitude != 0.0

    def times(self) -> np.ndarray:
        """Cycle time (in cycles) at the end of every increment: 1/n, 2/n, ..., cycles."""
        n = self.increments
        return np.arange(1, self.cycles * n + 1) / n

    def values(self, t) -> dict[str, np.ndarray]:
        """The drive (Q or delta), P, sigma_B and M at cycle times ``t``."""
        t = np.asarray(t, dtype=float)
        drive = self.amplitude * shape_value(self.shape, t)
        normal = self.normal + self.normal_amplitude * shape_value(
            self.shape, t + self.normal_phase / 360.0
        )
        bulk = self.bulk + self.bulk_amplitude * shape_value(
            self.shape, t + self.bulk_phase / 360.0
        )
        moment = (self.moment or 0.0) + self.moment_amplitude * shape_value(
            self.shape, t + self.moment_phase / 360.0
        )
        return {"drive": drive, "normal": normal, "bulk": bulk, "moment": moment}

    def names(self) -> list[str]:
        """Step names: ``press``, then ``c<cycle>.<increment>`` (e.g. c1.01 ... c10.40)."""
        width = len(str(self.increments))
        return [PRESS] + [
            f"c{k // self.increments + 1}.{k % self.increments + 1:0{width}d}"
            for k in range(self.cycles * self.increments)
        ]

    def steps(self) -> tuple[LoadStep, ...]:
        """The load history: the normal load (the waveform at t = 0), then one step per
        increment, each tagged with its cycle."""
        start = self.values(np.array([0.0]))
        values = self.values(self.times())
        names = self.names()
        cycles = [0] + [k // self.increments + 1 for k in range(self.cycles * self.increments)]
        out = []
        for k, name in enumerate(names):
            v = {key: (start if k == 0 else values)[key][0 if k == 0 else k - 1] for key in start}
            drive = 0.0 if k == 0 else float(v["drive"])
            loads = {"bulk": float(v["bulk"])} if self.has_bulk else {}
            force = self.control == "force"
            out.append(
                LoadStep(
                    name, float(v["normal"]), drive if force else 0.0, 1, loads,
                    delta=None if force else drive, cycle=cycles[k],
                    moment=float(v["moment"]) if self.has_moment else None,
                )
            )  # fmt: skip
        return tuple(out)
