"""Cycles to crack initiation from a critical-plane parameter, with run-out reported as such.

SWT and Fatemi-Socie invert the Basquin / Coffin-Manson strain-life curve (uniaxial and shear)
for 2N by root finding on log(2N); Findley uses the torsion Basquin curve scaled by
sqrt(1 + k^2) (closed form); MWCM uses the modified Wohler curves of Susmel and Lazzarin
(Fatigue Fract. Eng. Mater. Struct. 25 (2002) 63-78), interpolating the torsion (rho = 0) and
uniaxial (rho = 1) curves linearly in rho. ``stress_life`` reads the Basquin curve
sigma_ar = sigma_f' (2N)^b at the fully reversed amplitude a mean-stress correction gives
(:mod:`.mean_stress`: Goodman, Gerber, Morrow); ``strain_life`` inverts the Basquin /
Coffin-Manson curve of the normal strain amplitude, with Morrow's correction of the elastic
term. A life beyond ``runout_cycles`` is a run-out: ``cycles = inf``, ``runout = True`` and a
message, never a huge finite number.
"""

from __future__ import annotations

import math
import numbers

import attrs

from fretbem.validators import as_float, shown

from .errors import FatigueInputError
from .material import FatigueMaterial
from .mean_stress import CORRECTIONS_OF, mean_stress_correction

__all__ = ["LifeEstimate", "estimate_life"]


@attrs.frozen
class LifeEstimate:
    """Cycles to initiation by one method.

    Attributes
    ----------
    method : str
        Parameter name.
    parameter : float
        The parameter value the life is read from.
    cycles : float
        N (cycles, not reversals); ``inf`` for a run-out.
    runout : bool
        The parameter is below the curve at ``runout_cycles`` (or the fatigue limit).
    message : str
        Plain-language statement of the result.
    """

    method: str
    parameter: float
    cycles: float
    runout: bool
    message: str


#: the Basquin/Coffin-Manson constants the strain-life curve (SWT, strain_life) reads
STRAIN_LIFE_CONSTANTS = (
    "E",
    "fatigue_strength_coefficient",
    "fatigue_strength_exponent",
    "fatigue_ductility_coefficient",
    "fatigue_ductility_exponent",
)


def _runout(method: str, parameter: float, runout_cycles: float, why: str) -> LifeEstimate:
    return LifeEstimate(
        method,
        parameter,
        math.inf,
        True,
        f"run-out: {why} (no initiation within {runout_cycles:.3g} cycles)",
    )


def _invert(method: str, parameter: float, curve, runout_cycles: float) -> LifeEstimate:
    """Solve curve(2N) = parameter for N, curve decreasing in 2N."""
    if parameter <= 0.0:
        return _runout(method, parameter, runout_cycles, "the parameter is not positive")
    at_runout = curve(2.0 * runout_cycles)
    if parameter <= at_runout:
        return _runout(
            method,
            parameter,
            runout_cycles,
            f"parameter {parameter:.4g} <= {at_runout:.4g} at run-out",
        )
    if parameter >= curve(1.0):
        return LifeEstimate(
            method,
            parameter,
            0.5,
            False,
            "parameter above the curve at the first reversal: N <= 0.5",
        )
    from scipy.optimize import brentq

    log2n = brentq(
        lambda x: curve(10.0**x) - parameter, 0.0, math.log10(2.0 * runout_cycles), xtol=1e-12
    )
    cycles = 0.5 * 10.0**log2n
    return LifeEstimate(method, parameter, cycles, False, f"N = {cycles:.4g} cycles")


def _static(method: str, parameter: float, why: str) -> LifeEstimate:
    return LifeEstimate(method, parameter, 0.5, False, f"static failure: {why}: N <= 0.5")


def _stress_life(amplitude, mean, correction, material, runout_cycles) -> LifeEstimate:
    """Basquin at the corrected amplitude: N = (1/2) (sigma_ar / sigma_f')^(1/b)."""
    c = material.require(
        ("fatigue_strength_coefficient", "fatigue_strength_exponent"), "the stress-life life"
    )
    sf, b = c["fatigue_strength_coefficient"], c["fatigue_strength_exponent"]
    rule = mean_stress_correction(correction, material)
    if rule.static_failure(mean):
        return _static(
            "stress_life", amplitude, f"the mean stress {mean:.4g} MPa reaches the {correction} "
            f"limit {rule.limit:.4g} MPa"
        )  # fmt: skip
    equivalent = float(rule.equivalent_amplitude(amplitude, mean))
    if equivalent <= 0.0:
        return _runout("stress_life", equivalent, runout_cycles, "no stress amplitude")
    if material.has("fatigue_limit_range") and equivalent <= 0.5 * material.get(
        "fatigue_limit_range"
    ):
        limit = 0.5 * material.get("fatigue_limit_range")
        return _runout(
            "stress_life",
            equivalent,
            runout_cycles,
            f"sigma_ar {equivalent:.4g} <= the plain fatigue limit amplitude {limit:.4g} MPa",
        )
    if equivalent >= sf:
        return LifeEstimate(
            "stress_life", equivalent, 0.5, False, "sigma_ar >= sigma_f' at the first reversal"
        )
    cycles = 0.5 * (equivalent / sf) ** (1.0 / b)
    if cycles > runout_cycles:
        return _runout("stress_life", equivalent, runout_cycles, f"sigma_ar {equivalent:.4g} MPa")
    how = "no mean-stress correction" if correction == "none" else correction
    text = f"N = {cycles:.4g} cycles (sigma_ar = {equivalent:.4g} MPa, {how})"
    return LifeEstimate("stress_life", equivalent, cycles, False, text)


def _strain_life(amplitude, mean, correction, material, runout_cycles) -> LifeEstimate:
    """eps_a = (sigma_f' - sigma_m)/E (2N)^b + eps_f' (2N)^c (sigma_m = 0 without Morrow)."""
    c = material.require(STRAIN_LIFE_CONSTANTS, "the strain-life life")
    sf, b = c["fatigue_strength_coefficient"], c["fatigue_strength_exponent"]
    ef, cc = c["fatigue_ductility_coefficient"], c["fatigue_ductility_exponent"]
    shift = mean if correction == "morrow" else 0.0
    if shift >= sf:
        return _static(
            "strain_life", amplitude, f"the mean stress {mean:.4g} MPa reaches sigma_f' {sf:.4g} "
            "MPa (Morrow)"
        )  # fmt: skip

    def curve(x):
        return (sf - shift) / c["E"] * x**b + ef * x**cc

    life = _invert("strain_life", amplitude, curve, runout_cycles)
    if correction == "none" or life.runout:
        return life
    return attrs.evolve(life, message=f"{life.message} (morrow, sigma_m = {mean:.4g} MPa)")


def _number(where: str, value) -> float:
    """A number argument as a float (True, strings refused; an int past a float's range is
    infinite, which the checks below refuse in their words)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise FatigueInputError(f"{where} must be a number, got {shown(value)}")
    return as_float(value)


def estimate_life(
    method: str,
    parameter: float,
    material: FatigueMaterial,
    *,
    rho: float | None = None,
    mean_stress: float | None = None,
    correction: str = "none",
    runout_cycles: float = 1e7,
) -> LifeEstimate:
    """Cycles to initiation by ``method`` from its ``parameter`` value.

    ``rho`` (sigma_n,max / tau_a on the critical plane) is needed by MWCM, whose ``parameter``
    is the shear stress amplitude. ``stress_life`` takes the normal stress amplitude and
    ``strain_life`` the normal strain amplitude as ``parameter``, with the ``mean_stress``
    (MPa) of the cycle and a mean-stress ``correction`` (:data:`.mean_stress.CORRECTIONS_OF`);
    SWT, Findley, Fatemi-Socie and MWCM carry the mean stress themselves and refuse one.
    Raises :class:`~fretbem.fatigue.errors.MissingFatigueDataError` naming the missing
    constants.
    """
    parameter = _number("estimate_life parameter", parameter)
    runout_cycles = _number("runout_cycles", runout_cycles)
    rho = None if rho is None else _number("rho", rho)
    mean_stress = None if mean_stress is None else _number("mean_stress", mean_stress)
    if not runout_cycles > 1:
        raise FatigueInputError(f"runout_cycles must be > 1, got {runout_cycles}")
    if method in CORRECTIONS_OF:
        if correction not in CORRECTIONS_OF[method]:
            raise FatigueInputError(
                f"the {method} life takes the mean-stress corrections {CORRECTIONS_OF[method]}, "
                f"not {correction!r}"
            )
        if mean_stress is None and correction != "none":
            raise FatigueInputError(
                f"the {correction} correction needs the cycle's mean_stress (MPa)"
            )
        mean = 0.0 if mean_stress is None else float(mean_stress)
        if not (math.isfinite(parameter) and math.isfinite(mean)):
            raise FatigueInputError(
                f"the {method} life needs a finite amplitude and mean stress, got "
                f"{parameter}, {mean}"
            )
        life = _stress_life if method == "stress_life" else _strain_life
        return life(float(parameter), mean, correction, material, runout_cycles)
    if not math.isfinite(parameter) or (rho is not None and not math.isfinite(rho)):
        raise FatigueInputError(
            f"the {method} life needs a finite parameter (and rho), got {parameter}, {rho}"
        )
    if correction != "none":
        raise FatigueInputError(
            f"the {method} parameter carries the mean stress itself; mean-stress corrections "
            f"({correction!r}) apply to {tuple(CORRECTIONS_OF)}"
        )
    m = material
    if method == "swt":
        c = m.require(STRAIN_LIFE_CONSTANTS, "the SWT life")
        sf, b = c["fatigue_strength_coefficient"], c["fatigue_strength_exponent"]
        ef, cc = c["fatigue_ductility_coefficient"], c["fatigue_ductility_exponent"]

        def curve(x):
            return sf**2 / c["E"] * x ** (2 * b) + sf * ef * x ** (b + cc)

        return _invert(method, parameter, curve, runout_cycles)
    if method == "fatemi_socie":
        c = m.require(
            (
                "E",
                "nu",
                "shear_fatigue_strength_coefficient",
                "shear_fatigue_strength_exponent",
                "shear_fatigue_ductility_coefficient",
                "shear_fatigue_ductility_exponent",
            ),
            "the Fatemi-Socie life",
        )
        G = c["E"] / (2 * (1 + c["nu"]))

        def curve(x):
            return (
                c["shear_fatigue_strength_coefficient"]
                / G
                * x ** c["shear_fatigue_strength_exponent"]
                + c["shear_fatigue_ductility_coefficient"]
                * x ** c["shear_fatigue_ductility_exponent"]
            )

        return _invert(method, parameter, curve, runout_cycles)
    if method == "findley":
        c = m.require(
            ("findley_k", "shear_fatigue_strength_coefficient", "shear_fatigue_strength_exponent"),
            "the Findley life",
        )
        scale = math.sqrt(1 + c["findley_k"] ** 2) * c["shear_fatigue_strength_coefficient"]
        b0 = c["shear_fatigue_strength_exponent"]
        if m.has("torsion_fatigue_limit_amplitude"):
            limit = math.sqrt(1 + c["findley_k"] ** 2) * m.get("torsion_fatigue_limit_amplitude")
            if parameter <= limit:
                return _runout(
                    method,
                    parameter,
                    runout_cycles,
                    f"below the Findley fatigue limit {limit:.4g} MPa",
                )
        return _invert(method, parameter, lambda x: scale * x**b0, runout_cycles)
    if method == "mwcm":
        if rho is None:
            raise FatigueInputError("the MWCM life needs rho = sigma_n,max / tau_a")
        c = m.require(
            (
                "fatigue_limit_range",
                "torsion_fatigue_limit_amplitude",
                "fatigue_strength_exponent",
                "shear_fatigue_strength_exponent",
            ),
            "the MWCM life",
        )
        sigma_a = 0.5 * c["fatigue_limit_range"]
        tau_a_ref = c["torsion_fatigue_limit_amplitude"]
        tau_ref = tau_a_ref + (sigma_a / 2 - tau_a_ref) * rho
        k_rho = (
            -1 / c["shear_fatigue_strength_exponent"]
            + (-1 / c["fatigue_strength_exponent"] + 1 / c["shear_fatigue_strength_exponent"]) * rho
        )
        if parameter <= tau_ref or tau_ref <= 0:
            return _runout(
                method,
                parameter,
                runout_cycles,
                f"tau_a {parameter:.4g} <= reference {tau_ref:.4g} MPa at rho = {rho:.3g}",
            )
        cycles = runout_cycles * (tau_ref / parameter) ** k_rho
        return LifeEstimate(method, parameter, cycles, False, f"N = {cycles:.4g} cycles")
    raise FatigueInputError(
        f"unknown fatigue method {method!r}; choose from swt, findley, fatemi_socie, mwcm, "
        f"{', '.join(CORRECTIONS_OF)}"
    )
