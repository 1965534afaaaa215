"""Progress bars of the command line (tqdm on stderr): the steps of a long history, the
adaptive levels, the stresses and the fatigue assessment.

A bar shows only on a terminal, never with ``--quiet``, and only once its phase has lasted
:data:`DELAY` seconds, so short phases print nothing. Lower layers take a factory
``bars(description, total)`` returning an object with ``update(n)`` and ``close()``.
"""

from __future__ import annotations

import sys

__all__ = ["DELAY", "Bars", "NullBar"]

#: seconds a phase runs before its bar appears
DELAY = 2.0


class NullBar:
    """A bar that shows nothing (not a terminal, or --quiet)."""

    def update(self, n: int = 1) -> None:
        """Nothing to advance."""

    def close(self) -> None:
        """Nothing to close."""


class Bars:
    """Factory of progress bars on ``stream`` (stderr), enabled on a terminal unless quiet."""

    def __init__(self, *, quiet: bool = False, stream=None) -> None:
        self.stream = stream or sys.stderr
        isatty = getattr(self.stream, "isatty", None)
        self.enabled = not quiet and bool(isatty and isatty())

    def __call__(self, description: str, total: int | None = None):
        """A bar of ``total`` units (None: a counter) for the phase ``description``."""
        if not self.enabled:
            return NullBar()
        from tqdm import tqdm

        return tqdm(
            total=total, desc=f"fretbem: {description}", file=self.stream, leave=False,
            delay=DELAY, mininterval=0.5, dynamic_ncols=True,
        )  # fmt: skip

    def steps(self, total: int):
        """A ``progress(k, n, step)`` hook for :func:`fretbem.simulation.run`: one bar over
        the load steps."""
        bar = self("load steps", total)

        def hook(k: int, n: int, step) -> None:
            bar.update(1)
            if k == n:
                bar.close()

        return hook
