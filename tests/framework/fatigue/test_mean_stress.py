"""Mean-stress corrections: closed forms, the stress- and strain-life lives, the plane search,
the [fatigue] key and its refusals."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from fretbem.fatigue import (
    CattaneoMindlinCycle,
    FatigueInputError,
    FatigueMaterial,
    MeanStressCorrection,
    MissingFatigueDataError,
    critical_plane_parameters,
    estimate_life,
    fatigue_request_from_dict,
    fatigue_summary,
    mean_stress_correction,
    run_fatigue,
)

SF, B, EF, C, E = 1000.0, -0.1, 0.3, -0.6, 70000.0
MATERIAL = FatigueMaterial(
    "user",
    {
        "E": E,
        "nu": 0.3,
        "ultimate_strength": 600.0,
        "true_fracture_strength": 900.0,
        "fatigue_strength_coefficient": SF,
        "fatigue_strength_exponent": B,
        "fatigue_ductility_coefficient": EF,
        "fatigue_ductility_exponent": C,
    },
    {},
)
LIMITS = {"goodman": 600.0, "gerber": 600.0, "morrow": SF, "morrow_true_fracture": 900.0}


def _closed_form(name: str, amplitude: float, mean: float) -> float:
    if name == "none":
        return amplitude
    r = mean / LIMITS[name]
    return amplitude / (1.0 - r * r if name == "gerber" else 1.0 - r)


@pytest.mark.parametrize("name", ["none", "goodman", "gerber", "morrow", "morrow_true_fracture"])
@pytest.mark.parametrize("mean", [-150.0, 0.0, 80.0, 250.0])
def test_stress_life_is_basquin_at_the_corrected_amplitude(name, mean):
    """N = (1/2)(sigma_ar / sigma_f')^(1/b) with sigma_ar from the published equation."""
    amplitude = 200.0
    life = estimate_life(
        "stress_life", amplitude, MATERIAL, mean_stress=mean, correction=name, runout_cycles=1e12
    )
    equivalent = _closed_form(name, amplitude, mean)
    assert life.parameter == pytest.approx(equivalent, rel=1e-14)
    assert life.cycles == pytest.approx(0.5 * (equivalent / SF) ** (1 / B), rel=1e-12)
    if mean > 0 and name != "none":
        assert life.cycles < estimate_life("stress_life", amplitude, MATERIAL).cycles
    if name == "gerber":  # symmetric: a compressive mean harms as much as a tensile one
        mirrored = estimate_life(
            "stress_life", amplitude, MATERIAL, mean_stress=-mean, correction=name,
            runout_cycles=1e12,
        )  # fmt: skip
        assert mirrored.cycles == pytest.approx(life.cycles, rel=1e-12)


@pytest.mark.parametrize("cycles", [30.0, 2.0e3, 1.0e5, 5.0e6])
@pytest.mark.parametrize("mean", [-200.0, 0.0, 150.0])
def test_strain_life_morrow_inverts_its_curve(cycles, mean):
    """eps_a = (sigma_f' - sigma_m)/E (2N)^b + eps_f' (2N)^c, inverted to 1e-9."""
    x = 2.0 * cycles
    eps_a = (SF - mean) / E * x**B + EF * x**C
    life = estimate_life("strain_life", eps_a, MATERIAL, mean_stress=mean, correction="morrow")
    assert not life.runout
    assert life.cycles == pytest.approx(cycles, rel=1e-9)
    plain = estimate_life("strain_life", eps_a, MATERIAL, mean_stress=mean)  # no correction
    if mean == 0:
        assert plain.cycles == pytest.approx(life.cycles, rel=1e-12)
    else:  # a tensile mean shortens the life, a compressive one lengthens it
        assert (life.cycles < plain.cycles) == (mean > 0)


def test_static_failure_run_out_and_fatigue_limit():
    goodman = estimate_life("stress_life", 50.0, MATERIAL, mean_stress=600.0, correction="goodman")
    assert goodman.cycles == 0.5 and "static failure" in goodman.message
    gerber = estimate_life("stress_life", 50.0, MATERIAL, mean_stress=-700.0, correction="gerber")
    assert gerber.cycles == 0.5 and "static failure" in gerber.message
    morrow = estimate_life("strain_life", 1e-3, MATERIAL, mean_stress=SF, correction="morrow")
    assert morrow.cycles == 0.5 and "sigma_f'" in morrow.message
    low = estimate_life("stress_life", 100.0, MATERIAL, mean_stress=10.0, correction="goodman")
    assert low.runout and math.isinf(low.cycles)  # N = 5e9 > 1e7
    limited = MATERIAL.with_values({"fatigue_limit_range": 500.0})
    at_limit = estimate_life("stress_life", 240.0, limited, mean_stress=20.0, correction="goodman")
    assert at_limit.runout and "fatigue limit" in at_limit.message  # 240 / (1 - 1/30) < 250


def test_equivalent_amplitude_is_vectorised_and_infinite_at_the_limit():
    rule = mean_stress_correction("goodman", MATERIAL)
    assert rule == MeanStressCorrection("goodman", 600.0)
    out = rule.equivalent_amplitude([100.0, 100.0, 100.0], [0.0, 300.0, 600.0])
    np.testing.assert_allclose(out[:2], [100.0, 200.0], rtol=1e-15)
    assert np.isinf(out[2])


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda: estimate_life("swt", 1.0, MATERIAL, mean_stress=10.0, correction="goodman"),
         r"swt parameter carries the mean stress itself"),
        (lambda: estimate_life("strain_life", 1e-3, MATERIAL, mean_stress=1.0,
                               correction="goodman"),
         r"strain_life life takes the mean-stress corrections \('none', 'morrow'\)"),
        (lambda: estimate_life("stress_life", 100.0, MATERIAL, correction="gerber"),
         r"gerber correction needs the cycle's mean_stress"),
        (lambda: estimate_life("stress_life", 100.0, MATERIAL, mean_stress=math.nan,
                               correction="gerber"),
         r"finite amplitude and mean stress"),
        (lambda: MeanStressCorrection("soderberg", 1.0), r"unknown mean-stress correction"),
        (lambda: MeanStressCorrection("goodman", -5.0), r"limit stress > 0 MPa"),
        (lambda: MeanStressCorrection("goodman"), r"needs its limit stress"),
    ],
)  # fmt: skip
def test_refusals(call, match):
    with pytest.raises(FatigueInputError, match=match):
        call()


def test_missing_constant_is_named():
    bare = FatigueMaterial("bare", {"fatigue_strength_coefficient": SF}, {})
    with pytest.raises(MissingFatigueDataError, match=r"ultimate_strength"):
        mean_stress_correction("gerber", bare)


@pytest.mark.parametrize("mean", [-60.0, 0.0, 120.0])
def test_plane_search_finds_the_uniaxial_corrected_amplitude(mean):
    """sigma_xx = sigma_m + 150 sin t: the plane normal to x, sigma_ar = Goodman's, and the
    strain-life plane carries eps_a = 150 / E and the same mean."""
    t = np.linspace(0.0, 2 * math.pi, 73)
    stress = np.zeros((t.size, 1, 4))
    stress[:, 0, 0] = mean + 150.0 * np.sin(t)
    rule = mean_stress_correction("goodman", MATERIAL)
    out = critical_plane_parameters(
        stress, E=E, nu=0.3, methods=["stress_life", "strain_life"], mean_stress=rule
    )
    stress_life, strain_life = out["stress_life"], out["strain_life"]
    assert stress_life.value[0] == pytest.approx(150.0 / (1 - mean / 600.0), rel=1e-9)
    assert strain_life.value[0] == pytest.approx(150.0 / E, rel=1e-9)
    assert strain_life.normal_stress_mean[0] == pytest.approx(mean, abs=1e-9)
    for r in (stress_life, strain_life):
        assert min(r.normal_angle_deg[0], 180 - r.normal_angle_deg[0]) < 1e-6
        assert abs(r.normal_tilt_deg[0]) < 1e-6


def test_default_methods_are_unchanged():
    request = fatigue_request_from_dict({"material": "Ti-6Al-4V", "critical_distance": 0.05})
    assert "stress_life" not in request.methods and "strain_life" not in request.methods
    assert request.mean_stress == "none"


@pytest.mark.parametrize(
    ("table", "match"),
    [
        ({"mean_stress": "soderberg"}, r"\[fatigue\] mean_stress must be one of"),
        ({"mean_stress": 1}, r"\[fatigue\] mean_stress"),
        ({"mean_stress": "goodman"}, r'mean_stress = "goodman" corrects the stress_life'),
        ({"mean_stress": "goodman", "methods": ["swt"]}, r"carry the mean stress themselves"),
        ({"mean_stress": "goodman", "methods": ["stress_life", "strain_life"]},
         r'"goodman" does not apply to strain_life'),
        ({"mean_stress": "morrow_true_fracture", "methods": ["stress_life"]},
         r"mean_stress: the morrow_true_fracture mean-stress correction needs "
         r"\['true_fracture_strength'\]"),
    ],
)  # fmt: skip
def test_the_fatigue_key_refuses_what_cannot_be_done(table, match):
    with pytest.raises(FatigueInputError, match=match):
        fatigue_request_from_dict({"material": "Ti-6Al-4V", **table})


class _WithMeanBulk:
    """A closed-form cycle plus a constant bulk tension sigma_xx (a static preload)."""

    def __init__(self, cycle, mean):
        self.cycle, self.mean = cycle, mean
        self.n_steps, self.driver = cycle.n_steps, cycle.driver
        self.contact_half_width = cycle.contact_half_width

    def stress_at(self, points):
        stress = self.cycle.stress_at(points).copy()
        stress[..., 0] += self.mean
        stress[..., 3] += self.cycle.nu * self.mean  # plane strain
        return stress


def test_run_fatigue_with_morrow_on_the_cattaneo_mindlin_cycle():
    """The rig's cycle with a 100 MPa mean bulk stress: the hot-spot lives are estimate_life
    applied to the critical plane's amplitude and mean, and Morrow shortens them."""
    rig = _WithMeanBulk(CattaneoMindlinCycle(a=0.5, p0=300.0, f=0.6, tangential_ratio=0.5,
                                             sigma_bulk_max=80.0, nu=0.342), 100.0)  # fmt: skip
    lives = {}
    for name in ("none", "morrow"):
        request = fatigue_request_from_dict({
            "material": "Ti-6Al-4V", "critical_distance": 0.05, "methods":
            ["stress_life", "strain_life"], "mean_stress": name, "map_points": [21, 11],
        })  # fmt: skip
        report = run_fatigue(rig, request)
        for m in ("stress_life", "strain_life"):
            hot = report.methods[m].at_hot_spot
            amplitude = (
                hot.normal_stress_amplitude if m == "stress_life" else hot.normal_strain_amplitude
            )
            expected = estimate_life(
                m, float(amplitude[0]), request.material,
                mean_stress=float(hot.normal_stress_mean[0]), correction=name,
            )  # fmt: skip
            assert report.methods[m].life_hot_spot == expected
            lives[name, m] = expected.cycles
        summary = fatigue_summary(report)
        json.dumps(summary, allow_nan=False)
        assert summary["methods"]["stress_life"]["mean_stress_correction"] == name
    mean = float(report.methods["stress_life"].at_hot_spot.normal_stress_mean[0])
    assert mean > 0  # the surface tension peak has a tensile mean
    for m in ("stress_life", "strain_life"):
        assert lives["morrow", m] < lives["none", m]


def test_the_example_scene_runs_from_the_file():
    """examples/fretting_rig_mean_stress.toml through the scene reader and the pipeline (31
    pairs, a coarse in-plane map for speed): every method reports a life, the stress- and
    strain-life ones are estimate_life on their critical plane with Morrow's correction."""
    import attrs

    import fretbem
    from fretbem.scenes.file import load_scene

    path = Path(__file__).resolve().parents[3] / "examples" / "fretting_rig_mean_stress.toml"
    scene = load_scene(path)
    table = {**scene.extras["fatigue"], "map_points": [11, 5], "in_plane_only": True}
    scene = attrs.evolve(scene, extras={**scene.extras, "fatigue": table})
    report = fretbem.run_scene(scene, pairs=31).fatigue
    assert set(report.methods) == {"swt", "stress_life", "strain_life"}
    assert report.request.mean_stress == "morrow"
    for m in ("stress_life", "strain_life"):
        rep = report.methods[m]
        at = rep.at_hot_spot
        amplitude = at.normal_stress_amplitude if m == "stress_life" else at.normal_strain_amplitude
        assert rep.life_hot_spot == estimate_life(
            m, float(amplitude[0]), report.request.material,
            mean_stress=float(at.normal_stress_mean[0]), correction="morrow",
        )  # fmt: skip
        assert 0 < rep.life_hot_spot.cycles < rep.life_critical_distance.cycles < math.inf


def test_a_mean_beyond_the_ultimate_strength_is_a_static_failure(tmp_path):
    """A 1200 MPa preload on Ti-6Al-4V (sigma_u = 1042.5 MPa) with Goodman: sigma_ar is
    infinite outside the contact (under it the pressure lowers the mean), the hot-spot life
    is N <= 0.5 with the reason, and fatigue.json and the figures are still written (the
    parameter as null)."""
    from fretbem.fatigue import write_fatigue

    rig = _WithMeanBulk(CattaneoMindlinCycle(a=0.5, p0=300.0, f=0.6, tangential_ratio=0.5,
                                             nu=0.342), 1200.0)  # fmt: skip
    request = fatigue_request_from_dict({
        "material": "Ti-6Al-4V", "critical_distance": 0.05, "methods": ["stress_life"],
        "mean_stress": "goodman", "map_points": [11, 5], "in_plane_only": True,
    })  # fmt: skip
    report = run_fatigue(rig, request)
    rep = report.methods["stress_life"]
    assert np.isinf(rep.map.value).any() and np.isfinite(rep.map.value).any()
    assert np.isinf(rep.at_hot_spot.value[0])
    assert rep.life_hot_spot.cycles == 0.5 and "static failure" in rep.life_hot_spot.message
    write_fatigue(tmp_path, report)
    data = json.loads((tmp_path / "fatigue.json").read_text())["methods"]["stress_life"]
    assert data["parameter_at_hot_spot"] is None
    assert data["life_at_hot_spot"]["cycles"] == 0.5
