"""Load-step prefixes already solved on one condensed problem, reused by later histories.

The state a load history reaches after its first k steps depends only on the condensed
problem, the contact law, the solver's settings, the rig and those k steps. The cases of a
sweep that share their first steps (in a P x Q map, the pure normal step of every case with
the same P) therefore solve them once: :func:`fretbem.simulation.run` given a
:class:`StepMemo` takes a prefix it holds instead of solving it again, with the iterations
and residuals its solve reported, and keeps the prefixes it solves.

A reused prefix is the state an identical standalone run reaches; the steps after it start
the Newton iteration on the same state and pattern, so their unknowns equal the standalone
run's to round-off (the solver's kept LU of the last pattern is another one's, which moves
the last bits only; tests/framework/solvers/test_step_memo.py).
"""

from __future__ import annotations

from typing import Any

import attrs
import numpy as np

#: bytes of states a memo holds before it starts again empty (about 20,000 steps of a
#: 61-pair history, 1,500 of a 961-pair one)
MEMO_BYTES = 64 * 2**20


@attrs.frozen(eq=False)
class Reached:
    """The end of one solved load step: the state and what its solve reported."""

    state: Any  #: the ContactState at the end of the step
    iterations: int
    residuals: tuple[float, ...]
    increments: tuple  #: the step's IncrementRecords

    @property
    def nbytes(self) -> int:
        """Bytes of its arrays (the state's and the increment records')."""
        arrays = [self.state.x, self.state.slip, self.state.states]
        for record in self.increments:
            arrays += [record.slip, record.pressure, record.shear, record.states]
        return sum(np.asarray(a).nbytes for a in arrays) + 200 * (1 + len(self.increments))


class StepMemo:
    """Solved step prefixes of the histories run on one condensed problem (a trie of steps).

    Holds the prefixes of one (problem, pair, law, solver, rig) at a time: another of them
    starts it afresh. Emptied when it would hold more than ``capacity`` bytes.
    """

    def __init__(self, capacity: int = MEMO_BYTES) -> None:
        self.capacity = int(capacity)
        self._owner: tuple | None = None
        self._root: dict = {}
        self.nbytes = self.generation = 0
        self.hits = self.misses = 0

    def cursor(self, problem, simulation) -> _Cursor | None:
        """A walk along ``simulation``'s steps on ``problem`` (None: settings not hashable)."""
        settings = (getattr(simulation, "law", None), simulation.solver, simulation.rig)
        try:
            hash(settings)
        except TypeError:
            return None
        owner = self._owner
        same = owner is not None and owner[0] is problem and owner[1] is simulation.pair
        if not same or owner[2] != settings:
            self._owner = (problem, simulation.pair, settings)
            self.clear()
        return _Cursor(self, len(simulation.steps))

    def clear(self) -> None:
        """Forget every prefix."""
        self._root, self.nbytes = {}, 0
        self.generation += 1


class _Cursor:
    """One history's walk along the trie: ``find`` the next step, else ``keep`` it solved."""

    def __init__(self, memo: StepMemo, steps: int) -> None:
        self.memo, self.left = memo, steps
        self.node: dict | None = memo._root
        self.generation = memo.generation

    def _alive(self) -> bool:
        return self.node is not None and self.generation == self.memo.generation

    def find(self, load) -> Reached | None:
        """The next step's end if this prefix was solved before (the walk moves past it)."""
        entry = self.node.get(load) if self._alive() else None
        if entry is None:
            self.memo.misses += 1
            return None
        self.memo.hits += 1
        self.left -= 1
        self.node = entry[1]
        return entry[0]

    def keep(self, load, reached: Reached) -> None:
        """Keep the next step, just solved (the last step of a history is not kept: only a
        repeated case would take it)."""
        self.left -= 1
        memo = self.memo
        if not self._alive() or self.left <= 0:
            self.node = None
            return
        size = reached.nbytes
        if memo.nbytes + size > memo.capacity:
            memo.clear()
            self.node = None
            return
        children: dict = {}
        self.node[load] = (reached, children)
        memo.nbytes += size
        self.node = children


__all__ = ["MEMO_BYTES", "Reached", "StepMemo"]
