"""A run's result as an xarray Dataset: dims step and pair, coords x and the step names.

Variables: p, q, un, ut, slip, state (step, pair); the closed form's p_exact, q_exact where
one applies; per step P, Q, sigma_B, the errors and estimates, iterations and times; the
zones (contact extent, stick and slip zones NaN-padded, the closed form's [e - c, e + c])
and the result checks. Global attributes: the scene facts, Hertz a and p0, the accuracy
record and the timings.
"""

from __future__ import annotations

import math

import numpy as np

from fretbem.contact.law import STATE_NAMES
from fretbem.contact.zones import step_zones
from fretbem.verification.errors import ERROR_KEYS
from fretbem.verification.theory import hertz_numbers, theory_stick_zones

from .cf import CONVENTIONS, attributes, clean_attrs

__all__ = ["run_dataset"]

ESTIMATE_NAMES = {k: "est" + k[1:] for k in ERROR_KEYS}


def _var(dims, values, name: str, **extra) -> tuple:
    return (dims, values, {**attributes(name), **extra})


def _padded(rows: list[list[tuple]], width: int) -> np.ndarray:
    """(steps, most zones, width) with NaN where a step has fewer zones."""
    most = max([len(r) for r in rows] + [1])
    out = np.full((len(rows), most, width), np.nan)
    for k, row in enumerate(rows):
        for j, zone in enumerate(row):
            out[k, j, : len(zone)] = zone
    return out


def _pair_positions(steps) -> np.ndarray:
    x = np.asarray(steps[0].x, float)
    for step in steps[1:]:
        if np.asarray(step.x).shape != x.shape or not np.allclose(step.x, x, rtol=0, atol=0):
            raise ValueError("the steps of one result must share their pairs to be labelled")
    return x


def run_dataset(result):
    """The run as an :class:`xarray.Dataset` (see the module docstring for its contents)."""
    import xarray as xr

    steps = result.steps
    names = [s.name for s in steps]
    x = _pair_positions(steps)
    dims = ("step", "pair")
    ut = np.array([s.tangential_displacement for s in steps], float)
    slip = np.diff(ut, axis=0, prepend=np.zeros((1, ut.shape[1])))
    data = {
        "p": _var(dims, np.array([s.pressure for s in steps], float), "p"),
        "q": _var(dims, np.array([s.shear for s in steps], float), "q"),
        "un": _var(dims, np.array([s.normal_displacement for s in steps], float), "un"),
        "ut": _var(dims, ut, "ut"),
        "slip": _var(dims, slip, "slip"),
        "state": _var(
            dims,
            np.array([s.states for s in steps], np.int8),
            "state",
            flag_values=np.arange(len(STATE_NAMES), dtype=np.int8),
            flag_meanings=" ".join(STATE_NAMES),
        ),
        "P": _var("step", np.array([s.normal for s in steps], float), "P"),
        "Q": _var("step", np.array([s.tangential for s in steps], float), "Q"),
        "M": _var("step", np.array([getattr(s, "moment", math.nan) for s in steps], float), "M"),
        "theta": _var("step", np.array([getattr(s, "rotation", 0.0) for s in steps]), "theta"),
        "tilt": _var("step", np.array([getattr(s, "tilt", 0.0) for s in steps], float), "tilt"),
        "sigma_B": _var(
            "step", np.array([float((s.loads or {}).get("bulk", 0.0)) for s in steps]), "sigma_B"
        ),
        "integral_p": _var("step", np.array([s.resultant[0] for s in steps], float), "integral_p"),
        "integral_q": _var("step", np.array([s.resultant[1] for s in steps], float), "integral_q"),
        "iterations": _var("step", np.array([s.iterations for s in steps], np.int32), "iterations"),
        "seconds": _var("step", np.array([s.seconds for s in steps], float), "seconds"),
    }
    if all(s.exact is not None for s in steps):
        data["p_exact"] = _var(dims, np.array([s.exact[0] for s in steps], float), "p_exact")
        data["q_exact"] = _var(dims, np.array([s.exact[1] for s in steps], float), "q_exact")
    for key in ERROR_KEYS:
        errors = [(s.errors or {}).get(key) for s in steps]
        if any(e is not None for e in errors):
            data[key] = _var("step", np.array([math.nan if e is None else e for e in errors]), key)
        estimates = [(s.estimate or {}).get(key) for s in steps]
        if any(e is not None for e in estimates):
            name = ESTIMATE_NAMES[key]
            values = np.array([math.nan if e is None else e for e in estimates])
            data[name] = _var("step", values, name)
    zones = [step_zones(s) for s in steps]
    data["contact"] = _var(
        ("step", "edge"),
        np.array([z.contact if z.contact else (math.nan, math.nan) for z in zones], float),
        "contact",
    )
    data["stick_zone"] = _var(
        ("step", "stick_zone_index", "edge"),
        _padded([list(z.stick) for z in zones], 2),
        "stick_zone",
    )
    slips = _padded([[(a, b, 1.0 if s == "+" else -1.0) for a, b, s in z.slip] for z in zones], 3)
    data["slip_zone"] = _var(("step", "slip_zone_index", "edge"), slips[..., :2], "slip_zone")
    data["slip_zone_sign"] = _var(
        ("step", "slip_zone_index"), np.nan_to_num(slips[..., 2]).astype(np.int8), "slip_zone_sign"
    )
    reference = result.simulation.reference
    if reference is not None:
        theory = theory_stick_zones(reference, [s.tangential for s in steps])
        data["theory_stick_zone"] = _var(("step", "edge"), np.array(theory), "theory_stick_zone")
    checks = [s.checks or {} for s in steps]
    check_names = sorted({name for c in checks for name in c})
    if check_names:

        def table(field, fill):
            return np.array(
                [[getattr(c[n], field) if n in c else fill for n in check_names] for c in checks]
            )

        data["check_residual"] = _var(
            ("step", "check"), table("residual", math.nan).astype(float), "check_residual"
        )
        data["check_limit"] = _var(
            ("step", "check"), table("limit", math.nan).astype(float), "check_limit"
        )
        data["check_passed"] = _var(
            ("step", "check"), table("passed", False).astype(np.int8), "check_passed"
        )
    coords = {
        "step": ("step", np.array(names, dtype=str), {"long_name": "load step name"}),
        "x": ("pair", x, attributes("x")),
        "edge": ("edge", np.array(["from", "to"]), {"long_name": "zone end"}),
    }
    if check_names:
        coords["check"] = ("check", np.array(check_names, dtype=str), {"long_name": "result check"})
    return xr.Dataset(data, coords=coords, attrs=clean_attrs(_global_attrs(result)))


def _global_attrs(result) -> dict:
    info = result.describe()
    out = {
        "Conventions": CONVENTIONS,
        "title": f"fretbem run: {getattr(result.simulation, 'name', 'simulation')}",
        "source": "fretbem (2D BEM frictional contact)",
        "units_system": "mm, N, MPa; forces per unit thickness (N/mm)",
        "sign_conventions": "p > 0 in compression on the lower body; q is the traction of the "
        "upper body on the lower along +x; un, ut: upper minus lower; sigma_B > 0 in tension; "
        "errors are fractions of p0 (pressure) and f p0 (shear)",
        "basis": info.get("basis"),
        "degree": info.get("degree"),
        "pairs": info.get("pairs"),
        "dofs": info.get("dofs"),
        "friction": info.get("friction"),
        "solver": info.get("solver"),
        "models": info.get("models"),
        "timings_seconds": dict(result.timings),
    }
    hertz = hertz_numbers(result.simulation.reference)
    if hertz is not None:
        out.update(hertz_P=hertz["P"], hertz_a=hertz["a"], hertz_p0=hertz["p0"])
        reference = result.simulation.reference
        out["closed_form"] = type(getattr(reference, "closed_form", reference)).__name__
    accuracy = result.accuracy
    if accuracy is not None:
        record = accuracy.as_dict()
        out["accuracy_mesh"] = record.get("mesh")
        out["accuracy_levels"] = list(record.get("levels", []))
        out["estimate_reason"] = record.get("estimate_reason")
        out["accuracy"] = record
    return out
