"""
Life solver: published worked examples and the mean-stress corrections
======================================================================

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
and SWT's own mean-stress effect (sigma_max in the parameter) in the elastic range against
its closed form N = (1/2)(sqrt(sigma_max sigma_a)/sigma_f')^(1/b) for means from -100 to
+150 MPa.

**Mean-stress corrections.** The ``stress_life`` method reads the Basquin curve at the fully
reversed amplitude sigma_ar that a correction gives (:mod:`fretbem.fatigue.mean_stress`).
FatPy's issues 37 (Gerber, after Suresh) and 38 (Morrow with the true fracture strength,
after J. Draper, *Modern Metal Fatigue Analysis*, 2008) publish two worked cycles, again a
secondary source: sigma_f' = 475.4 MPa, b = -0.078, sigma_a = 180 MPa, sigma_m = 100 MPa,
with sigma_u = 700 MPa (Gerber: sigma_aeq = 183.8 MPa, N = 98104) and sigma~_fB = 770 MPa
(Morrow: 206.9 MPa, N = 21475). Every correction (Goodman, Gerber, Morrow with sigma_f' and
with sigma~_fB) is also checked against its closed form for means from -200 to +200 MPa, and
the ``strain_life`` method's Morrow correction against its curve and, in the elastic range,
against the stress-life Morrow correction (the two are the same equation there).

**Tolerances.** Half a cycle on N (the published values differ by their rounding),
0.05 MPa on P_SWT and 0.051 MPa on sigma_ar (half the published 0.1 MPa step; Gerber's
183.75 MPa is an exact tie, published as 183.8), 1e-9 relative on the closed forms (the root
finder's tolerance is 1e-12 in log10 2N; Basquin's inversion is itself a closed form).
"""

# %%
import math

import matplotlib.pyplot as plt
import numpy as np

from fretbem.fatigue import FatigueMaterial, critical_plane_parameters, estimate_life
from fretbem.verification.published_lives import (
    STRESS_LIFE_WORKED_CASES,
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

# %%
# The two published stress-life cycles, and the corrections side by side: the life at
# sigma_a = 180 MPa as the mean stress grows (sigma_u = 700 MPa, sigma~_fB = 770 MPa, the
# worked cases' Basquin constants). Goodman and Morrow credit a compressive mean; Gerber's
# parabola is symmetric, so it does not; Morrow with sigma_f' = 475.4 MPa is the harshest
# because sigma_f' is the smallest limit stress here.
for worked in STRESS_LIFE_WORKED_CASES:
    done = estimate_life(
        "stress_life",
        worked.stress_amplitude,
        FatigueMaterial("worked", worked.constants(), {}),
        mean_stress=worked.mean_stress,
        correction=worked.correction,
        runout_cycles=1e9,
    )
    print(
        f"{worked.correction}: sigma_ar = {done.parameter:.3f} MPa "
        f"(published {worked.published_equivalent_amplitude}), N = {done.cycles:.2f} "
        f"(published {worked.published_cycles:.0f})"
    )

limits = FatigueMaterial(
    "limits",
    {"fatigue_strength_coefficient": 475.4, "fatigue_strength_exponent": -0.078,
     "ultimate_strength": 700.0, "true_fracture_strength": 770.0},
    {},
)  # fmt: skip
means = np.linspace(-300.0, 250.0, 56)
fig, ax = plt.subplots(figsize=(6, 4), layout="constrained")
for name in ("none", "goodman", "gerber", "morrow", "morrow_true_fracture"):
    lives = [
        estimate_life("stress_life", 180.0, limits, mean_stress=m, correction=name,
                      runout_cycles=1e15).cycles
        for m in means
    ]  # fmt: skip
    ax.semilogy(means, lives, label=name)
for worked in STRESS_LIFE_WORKED_CASES:
    ax.semilogy([worked.mean_stress], [worked.published_cycles], "kx", ms=9)
ax.set_xlabel(r"mean stress $\sigma_m$ (MPa), $\sigma_a$ = 180 MPa")
ax.set_ylabel("cycles N")
ax.set_title("stress life with each correction; x: FatPy's published lives")
ax.legend(fontsize=8)
