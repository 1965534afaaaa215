"""Isotropic linear elastic material, plane strain by default."""

from __future__ import annotations

import attrs

from .validators import flag_field, number_field, poisson_ratio


@attrs.frozen
class Material:
    """Young's modulus and Poisson's ratio of a homogeneous body.

    Attributes
    ----------
    E : float
        Young's modulus (> 0), MPa in the project's units.
    nu : float
        Poisson's ratio in (-1, 0.5).
    plane_stress : bool
        Plane stress instead of the default plane strain.
    """

    E: float = attrs.field(
        converter=number_field("Young's modulus, MPa", "give E in MPa", low=0.0, low_open=True)
    )
    nu: float = attrs.field(
        converter=number_field("Poisson's ratio", "give nu in (-1, 0.5)", check=poisson_ratio)
    )
    plane_stress: bool = attrs.field(
        default=False,
        converter=flag_field("give True for plane stress, False (the default) for plane strain"),
    )

    @property
    def shear_modulus(self) -> float:
        """mu = E / (2 (1 + nu))."""
        return self.E / (2.0 * (1.0 + self.nu))

    @property
    def kernel_nu(self) -> float:
        """Poisson's ratio to use in the plane-strain kernels (nu / (1 + nu) in plane stress)."""
        return self.nu / (1.0 + self.nu) if self.plane_stress else self.nu
