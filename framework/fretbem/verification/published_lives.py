"""Published worked examples of strain-life calculations, to check the life solver against.

Each case carries its inputs, the published answer and where it was published. The SWT case
is the test case of the open FatPy project (faberorg/FatPy issues 35 and 36, after S. Suresh,
Fatigue of Materials, 1998); the stress-life cases with the Gerber and Morrow mean-stress
corrections are its issues 37 (after Suresh) and 38 (after J. Draper, Modern Metal Fatigue
Analysis, 2008): secondary sources, stated as such in the docs.

fretbem's SWT parameter is sigma_n,max * eps_a (MPa); FatPy's is
P_SWT = sqrt(E eps_a sigma_max) (MPa): :func:`swt_stress` converts.
"""

from __future__ import annotations

import math

import attrs

__all__ = [
    "STRESS_LIFE_WORKED_CASES",
    "SWT_WORKED_CASES",
    "WorkedStressLifeCase",
    "WorkedSwtCase",
    "basquin_swt_cycles",
    "swt_stress",
]


@attrs.frozen
class WorkedSwtCase:
    """One published SWT life calculation (uniaxial, one load cycle).

    Attributes
    ----------
    name, source : str
    E : float
        Young's modulus, MPa.
    sigma_f, b, eps_f, c : float
        Basquin and Coffin-Manson constants sigma_f' (MPa), b, eps_f', c.
    strain_amplitude, stress_amplitude, mean_stress : float
        eps_a, sigma_a (MPa), sigma_m (MPa) of the cycle.
    published_swt_stress : float
        The published P_SWT = sqrt(E eps_a sigma_max), MPa.
    published_cycles : tuple of float
        The published lives N (cycles); two values where the source gives two roundings.
    """

    name: str
    source: str
    E: float
    sigma_f: float
    b: float
    eps_f: float
    c: float
    strain_amplitude: float
    stress_amplitude: float
    mean_stress: float
    published_swt_stress: float
    published_cycles: tuple[float, ...]

    @property
    def stress_max(self) -> float:
        """sigma_max = sigma_m + sigma_a."""
        return self.mean_stress + self.stress_amplitude

    @property
    def parameter(self) -> float:
        """fretbem's SWT parameter sigma_max * eps_a, MPa."""
        return self.stress_max * self.strain_amplitude

    def constants(self) -> dict[str, float]:
        """The constants under fretbem's names (FatigueMaterial.values)."""
        return {
            "E": self.E,
            "fatigue_strength_coefficient": self.sigma_f,
            "fatigue_strength_exponent": self.b,
            "fatigue_ductility_coefficient": self.eps_f,
            "fatigue_ductility_exponent": self.c,
        }


SWT_WORKED_CASES: tuple[WorkedSwtCase, ...] = (
    WorkedSwtCase(
        name="FatPy SWT test case",
        source=(
            "faberorg/FatPy, GitHub issues 35 ('Implement uniaxial SWT criterion', N = 277) "
            "and 36 (same inputs, N = 278), citing S. Suresh, Fatigue of Materials (1998)"
        ),
        E=162000.0,
        sigma_f=475.4,
        b=-0.078,
        eps_f=0.612,
        c=-0.62,
        strain_amplitude=0.0135,
        stress_amplitude=290.0,
        mean_stress=10.0,
        published_swt_stress=810.0,
        published_cycles=(277.0, 278.0),
    ),
)


@attrs.frozen
class WorkedStressLifeCase:
    """One published stress-life calculation with a mean-stress correction (one load cycle).

    Attributes
    ----------
    name, source : str
    correction : str
        fretbem's name of the correction (:data:`fretbem.fatigue.mean_stress.CORRECTIONS`).
    sigma_f, b : float
        Basquin constants sigma_f' (MPa) and b.
    limit_constant : str
        The material constant the mean stress is divided by, under fretbem's name.
    limit : float
        Its value, MPa (sigma_u for Gerber, the true fracture strength for Morrow here).
    stress_amplitude, mean_stress : float
        sigma_a and sigma_m of the cycle, MPa.
    published_equivalent_amplitude : float
        The published sigma_aeq, MPa (rounded to 0.1 MPa).
    published_cycles : float
        The published life N, cycles (rounded to one cycle).
    """

    name: str
    source: str
    correction: str
    sigma_f: float
    b: float
    limit_constant: str
    limit: float
    stress_amplitude: float
    mean_stress: float
    published_equivalent_amplitude: float
    published_cycles: float

    def constants(self) -> dict[str, float]:
        """The constants under fretbem's names (FatigueMaterial.values)."""
        return {
            "fatigue_strength_coefficient": self.sigma_f,
            "fatigue_strength_exponent": self.b,
            self.limit_constant: self.limit,
        }


STRESS_LIFE_WORKED_CASES: tuple[WorkedStressLifeCase, ...] = (
    WorkedStressLifeCase(
        name="FatPy Gerber test case",
        source=(
            "faberorg/FatPy, GitHub issue 37 ('Implement stress-life prediction function based "
            "on the Gerber mean-stress correction'), citing S. Suresh, Fatigue of Materials (1998)"
        ),
        correction="gerber",
        sigma_f=475.4,
        b=-0.078,
        limit_constant="ultimate_strength",
        limit=700.0,
        stress_amplitude=180.0,
        mean_stress=100.0,
        published_equivalent_amplitude=183.8,
        published_cycles=98104.0,
    ),
    WorkedStressLifeCase(
        name="FatPy Morrow test case",
        source=(
            "faberorg/FatPy, GitHub issue 38 ('Implement stress-life prediction function based "
            "on the Morrow mean-stress correction'), citing J. Draper, Modern Metal Fatigue "
            "Analysis (2008)"
        ),
        correction="morrow_true_fracture",
        sigma_f=475.4,
        b=-0.078,
        limit_constant="true_fracture_strength",
        limit=770.0,
        stress_amplitude=180.0,
        mean_stress=100.0,
        published_equivalent_amplitude=206.9,
        published_cycles=21475.0,
    ),
)


def swt_stress(E: float, parameter: float) -> float:
    """P_SWT = sqrt(E sigma_max eps_a) in MPa from fretbem's parameter sigma_max eps_a."""
    return math.sqrt(E * parameter)


def basquin_swt_cycles(
    sigma_f: float, b: float, stress_max: float, stress_amplitude: float
) -> float:
    """N = (1/2) (sqrt(sigma_max sigma_a) / sigma_f')^(1/b): SWT in the elastic (Basquin) range.

    The closed form of the SWT life when the Coffin-Manson term is negligible (eps_f' = 0):
    the mean-stress correction SWT makes to a Basquin curve.
    """
    return 0.5 * (math.sqrt(stress_max * stress_amplitude) / sigma_f) ** (1.0 / b)
