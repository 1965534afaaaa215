"""Units, long names and sign conventions of every labelled variable (CF-style attributes).

Units are UDUNITS strings as the CF conventions ask ("mm", "MPa", "N mm-1", "1" for
dimensionless); the sign conventions are the ones of results.csv and units.json.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping

__all__ = ["CONVENTIONS", "VARIABLES", "attributes", "clean_attrs"]

CONVENTIONS = "CF-1.10"

#: name -> (units, long_name, comment)
VARIABLES: dict[str, tuple[str, str, str]] = {
    "x": ("mm", "pair position", "x coordinate of the lower body's contact node"),
    "p": ("MPa", "contact pressure", "on the lower body, > 0 in compression"),
    "q": ("MPa", "shear traction", "of the upper body on the lower, along +x (the pair tangent)"),
    "un": (
        "mm",
        "relative normal displacement",
        "upper minus lower, along the lower normal",
    ),
    "ut": (
        "mm",
        "relative tangential displacement",
        "accumulated slip, upper minus lower, along +x",
    ),
    "slip": (
        "mm",
        "slip increment of the step",
        "change of ut since the previous step (the first step: ut), along +x",
    ),
    "state": ("1", "pair state", "0 separated, 1 stick, 2 slip"),
    "p_exact": ("MPa", "closed-form contact pressure", "Hertz, at the pair positions"),
    "q_exact": (
        "MPa",
        "closed-form shear traction",
        "Cattaneo-Mindlin, Mindlin-Deresiewicz or Nowell-Hills, at the pair positions",
    ),
    "P": ("N mm-1", "normal load", "per unit thickness, > 0 presses the upper body down"),
    "Q": ("N mm-1", "tangential load", "per unit thickness on the upper body, along +x"),
    "sigma_B": ("MPa", "bulk stress of the specimen", "along x, > 0 in tension"),
    "M": (
        "N",
        "moment of the pad's loading block on the pad",
        "N mm per mm thickness, about the rig's pivot, counterclockwise > 0",
    ),
    "theta": (
        "rad",
        "rotation of the actuator holding the pad's block",
        "counterclockwise > 0: the block's own rotation plus M / k_r",
    ),
    "tilt": ("rad", "rotation of the pad's loading block", "about the pivot, counterclockwise > 0"),
    "e_p_max": ("1", "max pressure error", "max |p - p_exact| / p0"),
    "e_q_max": ("1", "max shear error", "max |q - q_exact| / (f p0)"),
    "e_p_l2": ("1", "RMS pressure error", "RMS of p - p_exact over the zone, / p0"),
    "e_q_l2": ("1", "RMS shear error", "RMS of q - q_exact over the zone, / (f p0)"),
    "est_p_max": ("1", "estimated max pressure error", "from two mesh levels, / p0"),
    "est_q_max": ("1", "estimated max shear error", "from two mesh levels, / (f p0)"),
    "est_p_l2": ("1", "estimated RMS pressure error", "from two mesh levels, / p0"),
    "est_q_l2": ("1", "estimated RMS shear error", "from two mesh levels, / (f p0)"),
    "integral_p": ("N mm-1", "integral of p over the contact face", ""),
    "integral_q": ("N mm-1", "integral of q over the contact face", ""),
    "iterations": ("1", "Newton iterations of the step", ""),
    "seconds": ("s", "wall time of the step", ""),
    "contact": ("mm", "contact extent", "x of the first and last pair in contact"),
    "stick_zone": ("mm", "computed stick zones", "from the first to the last stick pair"),
    "slip_zone": ("mm", "computed slip zones", "from the first to the last slip pair"),
    "slip_zone_sign": ("1", "sign of a slip zone's mean shear", "+1 or -1; 0: no zone"),
    "theory_stick_zone": (
        "mm",
        "closed-form stick zone",
        "[e - c, e + c], offset e by the bulk stress",
    ),
    "check_residual": ("1", "result check residual", "see fretbem.verification.checks"),
    "check_limit": ("1", "result check limit", "the check passes when residual <= limit"),
    "check_passed": ("1", "result check passed", "1 passed, 0 failed"),
    "sigma_xx": ("MPa", "stress sigma_xx", "> 0 in tension"),
    "sigma_yy": ("MPa", "stress sigma_yy", "> 0 in tension"),
    "sigma_xy": ("MPa", "stress sigma_xy", ""),
    "sigma_zz": ("MPa", "stress sigma_zz", "nu (sigma_xx + sigma_yy) in plane strain"),
    "von_mises": ("MPa", "von Mises stress", "sigma_zz included"),
    "depth": ("mm", "depth below the contact surface", "at the same x"),
    "y": ("mm", "y coordinate", "global frame"),
}


def attributes(name: str) -> dict:
    """``units``, ``long_name`` and (when there is one) ``comment`` of a variable."""
    units, long_name, comment = VARIABLES[name]
    out = {"units": units, "long_name": long_name}
    if comment:
        out["comment"] = comment
    return out


def _clean(value):
    if value is None:
        return None
    if isinstance(value, bool):
        return int(value)
    if isinstance(value, (int, str)):
        return value
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, Mapping):
        return json.dumps({k: v for k, v in value.items()}, default=str)
    if isinstance(value, (list, tuple)):
        if all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value) and value:
            return list(value)
        return json.dumps(list(value), default=str)
    return str(value)


def clean_attrs(attrs: Mapping) -> dict:
    """Attributes netCDF can hold: no None or NaN (dropped), booleans as 0/1, mappings and
    mixed lists as JSON text."""
    out = {}
    for key, value in attrs.items():
        value = _clean(value)
        if value is not None:
            out[key] = value
    return out
