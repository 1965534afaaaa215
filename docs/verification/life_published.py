"""
Life solver: a published SWT worked example and the mean-stress correction
==========================================================================

**Source.** The test case of the open fatigue library FatPy (GitHub, faberorg/FatPy,
issues 35 "Implement uniaxial SWT criterion" and 36, after S. Suresh, *Fatigue of
Materials*, 1998). It is a secondary source: the numbers are those the issues give, not
re-derived from the book.

**Inputs.** sigma_f' = 475.4 MPa, b = -0.078, eps_f' = 0.612, c = -0.62, E = 162 GPa; one
cycle with strain amplitude eps_a = 0.0135, stress amplitude sigma_a = 290 MPa and mean
sigma_m = 10 MPa. **Published:** P_SWT = sqrt(E eps_a sigma_max) = 810.0 MPa and
N = 277 (issue 35) or 278 cycles (issue 36), the root of
sigma_max eps_a = (sigma_f'^2/E)(2N)^(2b) + sigma_f' eps_f' (2N)^(b+c).

**Compared.** :func:`fretbem.fatigue.estimate_life` on fretbem's parameter
sigma_max eps_a = 4.05 MPa; the 3D critical-plane search
(:func:`fretbem.fatigue.critical_plane_parameters`) on the uniaxial cycle, with the modulus
taken as the cycle's secant sigma_a / eps_a because it computes strains by Hooke's law;
and, since fretbem's mean-stress correction is SWT itself (sigma_max in the parameter; it
has no separate Goodman, Gerber or Morrow correction), the SWT life in the elastic range
against its closed form N = (1/2)(sqrt(sigma_max sigma_a)/sigma_f')^(1/b) for means from
-100 to +150 MPa.

**Tolerances.** Half a cycle on N (the two published values differ by their rounding),
0.05 MPa on P_SWT (the published precision), 1e-9 relative on the closed form (the root
finder's tolerance is 1e-12 in log10 2N).
"""

# %%
import math

import matplotlib.pyplot as plt
import numpy as np

from fretbem.fatigue import FatigueMaterial, critical_plane_parameters, estimate_life
from fretbem.verification.published_lives import (
    SWT_WORKED_CASES,
    basquin_swt_cycles,
    swt_stress,
)

case = SWT_WORKED_CASES[0]
material = FatigueMaterial("worked", case.constants(), {})
life = estimate_life("swt", case.parameter, material)
print(f"P_SWT = {swt_stress(case.E, case.parameter):.2f} MPa (published 810.0)")
print(f"N = {life.cycles:.3f} cycles (published {case.published_cycles})")

t = np.linspace(0.0, 2 * math.pi, 73)
stress = np.zeros((t.size, 1, 4))
stress[:, 0, 0] = case.mean_stress + case.stress_amplitude * np.sin(t)
plane = critical_plane_parameters(
    stress, E=case.stress_amplitude / case.strain_amplitude, nu=0.3, methods=["swt"]
)["swt"]
print(
    f"plane search: sigma_max eps_a = {plane.value[0]:.6f} MPa on the plane at "
    f"{plane.normal_angle_deg[0]:.1f} deg (expected {case.parameter:.6f} MPa, 0 deg)"
)

# %%
# The strain-life curve with the worked point, and SWT's mean-stress effect in the elastic
# range (eps_f' = 1e-15, a negligible Coffin-Manson term): the life falls as the mean
# stress grows at a fixed amplitude.
reversals = np.logspace(0, 7, 200)
curve = (case.sigma_f**2 / case.E) * reversals ** (2 * case.b) + (
    case.sigma_f * case.eps_f * reversals ** (case.b + case.c)
)
basquin = FatigueMaterial(
    "basquin",
    {**case.constants(), "fatigue_ductility_coefficient": 1e-15},
    {},
)
means = np.linspace(-150.0, 200.0, 15)
amplitude = 180.0
solver = [
    estimate_life("swt", (m + amplitude) * amplitude / case.E, basquin, runout_cycles=1e12).cycles
    for m in means
]
exact = [basquin_swt_cycles(case.sigma_f, case.b, m + amplitude, amplitude) for m in means]
worst = max(abs(s - e) / e for s, e in zip(solver, exact, strict=True))
print(f"mean-stress sweep: largest relative difference from the closed form {worst:.1e}")

fig, axes = plt.subplots(1, 2, figsize=(10, 4), layout="constrained")
axes[0].loglog(reversals / 2, curve, "k-", label="SWT curve")
axes[0].loglog([life.cycles], [case.parameter], "o", label=f"fretbem N = {life.cycles:.1f}")
axes[0].loglog([278.0], [case.parameter], "x", ms=10, label="published N = 278")
axes[0].set_xlabel("cycles N")
axes[0].set_ylabel(r"$\sigma_{max}\,\varepsilon_a$ (MPa)")
axes[0].legend()
axes[1].semilogy(means, solver, "o", label="fretbem (root finder)")
axes[1].semilogy(means, exact, "k-", label="closed form")
axes[1].set_xlabel(r"mean stress $\sigma_m$ (MPa), $\sigma_a$ = 180 MPa")
axes[1].set_ylabel("cycles N")
axes[1].legend()
