"""Units of a sweep's parameters and output columns, for map axes, colour bars and the
labelled (xarray) table: scene key paths by their last key, outputs by their name.

Units follow the scene's system (mm, N, MPa; forces per unit thickness). Dimensionless
quantities are "1" (the CF convention); names this table does not know get no unit rather
than a wrong one.
"""

from __future__ import annotations

import re

__all__ = ["axis_label", "unit_of"]

#: the last key of a scene key path (``load.P``, ``pad.radius``, ``load.Q[1]``)
SCENE_KEYS = {
    "P": "N/mm", "Q": "N/mm", "bulk": "MPa", "friction": "1", "E": "MPa", "nu": "1",
    "radius": "mm", "width": "mm", "height": "mm", "length": "mm", "thickness": "mm",
    "flat": "mm", "zone_width": "mm", "zone": "a (Hertz half-width)", "pairs": "1",
    "degree": "1", "tolerance": "1", "increments": "1", "delta": "mm", "approach": "mm",
    "cycles": "1", "P_amplitude": "N/mm", "P_phase": "degrees", "bulk_amplitude": "MPa",
    "bulk_phase": "degrees", "stiffness_x": "MPa", "stiffness_y": "MPa", "moment": "N mm/mm",
    "rotation": "rad", "M_amplitude": "N mm/mm", "M_phase": "degrees",
    "stiffness_rotation": "N mm/mm per rad", "pivot_height": "mm",
}  # fmt: skip
#: output columns, by their name before the step (``stick_width.B``) or method
OUTPUTS = {
    "P_max": "N/mm", "Q_peak": "N/mm", "friction": "1", "stick_width": "mm",
    "contact_width": "mm", "p_max": "MPa", "q_max": "MPa", "sxx_max": "MPa",
    "e_p_max": "fraction of p0", "e_q_max": "fraction of f p0", "iterations": "1",
    "solve_seconds": "s", "solve_cpu_seconds": "s", "assembly_seconds": "s",
    "dissipated_energy": "N mm/mm", "delta_amplitude": "mm", "Q_amplitude": "N/mm",
    "energy_ratio": "1", "transition_ratio": "1", "slip_amplitude_max": "mm", "cycles": "1",
    "M": "N mm/mm", "theta": "rad", "tilt": "rad", "M_amplitude": "N mm/mm",
    "theta_amplitude": "rad", "tilt_amplitude": "rad",
}  # fmt: skip
#: per-method fatigue columns (``swt.life``, ``mwcm.x``)
METHOD_COLUMNS = {"life": "cycles", "x": "mm", "depth": "mm"}
PARAMETER_UNITS = {
    "swt": "MPa", "findley": "MPa", "fatemi_socie": "1", "mwcm": "MPa", "stress_life": "MPa",
    "strain_life": "1",
}  # fmt: skip


def unit_of(name: str) -> str | None:
    """The unit of a sweep parameter path or output column (None when unknown)."""
    if name in OUTPUTS:
        return OUTPUTS[name]
    head, _, tail = name.partition(".")
    if head in OUTPUTS and tail:  # a per-step output: stick_width.B
        return OUTPUTS[head]
    if head in PARAMETER_UNITS and tail:
        return PARAMETER_UNITS[head] if tail == "parameter" else METHOD_COLUMNS.get(tail)
    last = re.sub(r"\[\d+\]$", "", name.rsplit(".", 1)[-1])
    return SCENE_KEYS.get(last)


def axis_label(name: str) -> str:
    """``name (unit)`` for an axis or a colour bar; ``name (-)`` when dimensionless."""
    unit = unit_of(name)
    if unit is None:
        return name
    return f"{name} ({'-' if unit == '1' else unit})"
