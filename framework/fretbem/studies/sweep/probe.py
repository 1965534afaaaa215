"""The default sweep engine's estimate of the work left, updated case by case.

The "auto" engine solves in its own process and hands the rest to a parallel engine once
the remaining serial work, estimated from the cases solved so far, pays for its start. The
estimate is kept up to date in constant time per case (a window of the last solves, the
group assemblies seen), so staying in this process costs what ``--serial`` costs.
"""

from __future__ import annotations

import statistics
from collections import deque
from collections.abc import Mapping, Sequence
from typing import Any

import attrs

#: cases solved in this process before the remaining work is estimated
PROBE_CASES = 5
#: the recent cases the per-case estimate is taken over
PROBE_WINDOW = 25


def queued_work(queue: Sequence[Any], scene: Any = None) -> tuple[int, int]:
    """(cases, groups other than ``scene``'s) of the queued tasks (``.scene``, ``.cases``);
    the tasks of one group share their representative scene object."""
    cases = sum(len(task.cases) for task in queue)
    groups = {id(task.scene) for task in queue} - {id(scene)}
    return cases, len(groups)


@attrs.define
class WorkProbe:
    """Serial CPU seconds the sweep's unsolved cases would take, from the rows solved so
    far: the median case (its whole CPU where measured, else its solve) of the last
    ``PROBE_WINDOW`` cases times the cases left, plus the median group assembly for every
    further group. ``peak`` keeps the largest estimate
    made and the cases solved when it was made (for the summary's note)."""

    solves: deque = attrs.field(factory=lambda: deque(maxlen=PROBE_WINDOW))
    assemblies: list = attrs.field(factory=list)
    solved: int = 0
    peak: tuple[float, int] | None = None

    def add(self, row: Mapping[str, Any], cpu: float | None = None) -> None:
        """Take one solved case's row (refused and failed cases carry no solve time) and,
        where the caller measured it, the CPU seconds of the whole case: its loading, output
        columns and functions (a stress column costs half the solve) besides the solve."""
        assembly = float(row.get("assembly_seconds") or 0.0)
        if "solve_seconds" in row:
            # CPU seconds where recorded: a busy machine stretches every process's wall time
            solve = float(row.get("solve_cpu_seconds", row["solve_seconds"]))
            if cpu is not None:  # the group's assembly is counted per group, not per case
                solve = max(solve, cpu - assembly)
            self.solves.append(solve)
            self.solved += 1
        if assembly:
            self.assemblies.append(assembly)

    def remaining(self, cases: int, groups: int) -> float | None:
        """Seconds for ``cases`` more cases in ``groups`` more groups (None: too few solved
        cases yet to tell)."""
        if len(self.solves) < PROBE_CASES:
            return None
        per_group = statistics.median(self.assemblies) if self.assemblies else 0.0
        seconds = statistics.median(self.solves) * cases + per_group * groups
        if self.peak is None or seconds > self.peak[0]:
            self.peak = (seconds, self.solved)
        return seconds


__all__ = ["PROBE_CASES", "PROBE_WINDOW", "WorkProbe", "queued_work"]
