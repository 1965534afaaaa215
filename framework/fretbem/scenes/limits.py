"""Up-front estimates of a scene's size and run time, refused with the estimate when hopeless.

Checked from the scene's keys alone, before any body is built: the boundary unknowns
(``[contact] pairs`` and the ``[mesh]`` element counts) give the dense BEM memory
(:mod:`fretbem.bem.resources`), the load history (``[load]`` steps times ``increments``)
gives the number of contact solves and the memory of the stored results. A run whose
estimate does not fit the machine's memory, or would take longer than :data:`MAX_SECONDS`,
is refused with the estimate and the key to change, instead of running until it is killed.
Per-increment cost measured on the reference scene (61 and 241 pairs, one BLAS thread:
about 1.4 and 5 ms), with a margin.
"""

from __future__ import annotations

import math

import attrs

from fretbem import registry
from fretbem.basis import points_per_element
from fretbem.bem import resources
from fretbem.bem.resources import MEMORY_FRACTION, _duration, _size
from fretbem.errors import ResourceLimitError

__all__ = ["MAX_SECONDS", "SceneEstimate", "check_scene", "estimate_scene"]

#: longest estimated run accepted (a day); longer histories are refused with the estimate
MAX_SECONDS = 24 * 3600.0
#: seconds per load increment: a constant part and a part growing as pairs^2 (condensed
#: contact system), measured 1.4 ms at 61 and 5 ms at 241 pairs, doubled
SECONDS_PER_INCREMENT = 2e-3
SECONDS_PER_INCREMENT_PAIR2 = 2e-7
#: bytes stored per step and pair (x, p, q, the relative displacements, states, unknowns,
#: the closed form's p and q: about 10 float arrays) and per step (the record itself)
BYTES_PER_STEP_PAIR = 10 * 8
BYTES_PER_STEP = 4096


@attrs.frozen
class SceneEstimate:
    """What a scene will cost: unknowns, memory (bytes) and time (seconds)."""

    dofs: int
    increments: int
    steps: int
    memory: float
    seconds: float
    results: float  # bytes of the stored step results

    def describe(self) -> str:
        """One line: unknowns, solves, memory and time."""
        return (
            f"about {self.dofs} boundary DOFs and {self.increments} contact solves, estimated "
            f"{_size(self.memory)} of memory and {_duration(self.seconds)}"
        )


def _collocation_points(scene) -> int:
    """Points on one body's boundary: the contact zone and the graded elements around it."""
    try:
        family = registry.get(scene.contact.basis)
        per, extra = points_per_element(family, scene.contact.degree)
    except Exception:
        per, extra = 2.0, 1.0
    mesh = scene.mesh
    elements = 2 * mesh.flank_elements + 2 * mesh.side_elements + mesh.top_elements
    return int(scene.contact.pairs + per * elements + extra)


def estimate_scene(scene, *, available: float | None = math.nan) -> SceneEstimate:
    """The memory and time the scene will need (both bodies, the whole history)."""
    pairs = scene.contact.pairs
    if scene.contact.mesh == "adaptive":
        pairs = scene.contact.budget
    dofs = 2 * 2 * (_collocation_points(scene) - scene.contact.pairs + pairs)
    dense = resources.estimate_resources(dofs, available=available)
    load = scene.load
    steps = len(load.steps) if load is not None else 0
    increments = sum(load.increments) if load is not None else 0
    solve = SECONDS_PER_INCREMENT + SECONDS_PER_INCREMENT_PAIR2 * pairs * pairs
    results = steps * (BYTES_PER_STEP + BYTES_PER_STEP_PAIR * pairs)
    return SceneEstimate(
        dofs=dofs,
        increments=increments,
        steps=steps,
        memory=dense.memory + results,
        seconds=dense.seconds + increments * solve,
        results=results,
    )


def check_scene(scene, *, max_seconds: float = MAX_SECONDS, available: float | None = math.nan):
    """The scene's estimate, or ResourceLimitError naming the key that makes it hopeless."""
    if available is not None and math.isnan(available):
        # the estimate does not depend on the reading: a reading of the last second serves
        # a small one (resources.RECENT_SECONDS; a sweep's or a study's next build)
        estimate = estimate_scene(scene, available=None)
        available = resources._available_for(estimate.memory)
    else:
        estimate = estimate_scene(scene, available=available)
    if available is not None and estimate.memory > MEMORY_FRACTION * available:
        if estimate.results > estimate.memory / 2:
            cause = (
                f"the load history's {estimate.steps} steps store about "
                f"{_size(estimate.results)} of results; split [load] into shorter runs"
            )
        else:
            cause = (
                "the dense BEM matrices grow as DOFs^2; lower [contact] pairs (or budget) and "
                "the [mesh] element counts"
            )
        raise ResourceLimitError(
            f"refusing to start: {estimate.describe()} (available memory: {_size(available)}); "
            f"{cause}"
        )
    if estimate.seconds > max_seconds:
        raise ResourceLimitError(
            f"refusing to start: {estimate.describe()}, more than the "
            f"{_duration(max_seconds)} limit; lower [load] increments (now "
            f"{estimate.increments} solves over {estimate.steps} steps) or the number of steps"
        )
    return estimate
