"""Published worked examples of strain-life calculations, to check the life solver against.

Each case carries its inputs, the published answer and where it was published. The SWT case
is the test case of the open FatPy project (faberorg/FatPy issues 35 and 36, after S. Suresh,
Fatigue of Materials, 1998): a secondary source, stated as such in the docs.

fretbem's SWT parameter is sigma_n,max * eps_a (MPa); FatPy's is
P_SWT = sqrt(E eps_a sigma_max) (MPa): :func:`swt_stress` converts.
"""

from __future__ import annotations

import math

import attrs

__all__ = ["SWT_WORKED_CASES", "WorkedSwtCase", "basquin_swt_cycles", "swt_stress"]


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
