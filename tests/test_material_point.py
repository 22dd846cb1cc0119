"""axmpm.material_point (axmpm/material_driver.py): the Python driver of one engine material point (issue #4)."""

import math

import numpy as np
import pytest

from axmpm import material_point
from axmpm.errors import ScenarioError
from axmpm.material_driver import drained_triaxial, validate_material, yield_ratio

E, NU = 1.0e6, 0.3
LAM = E * NU / ((1 + NU) * (1 - 2 * NU))
MU = E / (2 * (1 + NU))


def assert_named_error(material: dict, field: str, message: str) -> None:
    """The material is refused with an error that names ``field`` and says ``message``."""
    with pytest.raises(ScenarioError) as info:
        validate_material(material)
    text = str(info.value)
    assert field in text and message in text, text


def mc(phi=25.0, psi=0.0, c=0.0):
    return dict(model="mohr_coulomb", density=1550.0, youngs_modulus=E, poisson_ratio=NU,
                friction_angle=phi, dilation_angle=psi, cohesion=c)


def test_elastic_steps_equal_linear_elastic():
    # a small general strain path well inside the yield surface (confined, compressive)
    rng = np.random.default_rng(1)
    L = np.zeros((20, 5))
    L[:, 0] = -0.5 + 0.1 * rng.standard_normal(20)
    L[:, 3] = -0.5 + 0.1 * rng.standard_normal(20)
    L[:, 4] = -0.5 + 0.1 * rng.standard_normal(20)
    dt = 1e-4
    s0 = [-1e4, -1e4, -1e4, 0.0]
    plastic = material_point(mc(), L, dt, s0)
    elastic = material_point(dict(model="linear_elastic", density=1550.0, youngs_modulus=E,
                                  poisson_ratio=NU), L, dt, s0)
    np.testing.assert_allclose(plastic.stresses, elastic.stresses, rtol=0, atol=1e-9)
    assert np.all(plastic.state("plastic_shear_strain") == 0.0)
    # and Hooke by hand (no spin, so no Jaumann rotation)
    eps = L.sum(axis=0) * dt
    tr = eps[0] + eps[3] + eps[4]
    hooke = np.array(s0) + np.array([LAM * tr + 2 * MU * eps[0], LAM * tr + 2 * MU * eps[3],
                                     LAM * tr + 2 * MU * eps[4], 0.0])
    np.testing.assert_allclose(plastic.stresses[-1], hooke, rtol=1e-12, atol=1e-9)


def test_returns_pair_and_names():
    out = material_point(mc(), np.zeros((3, 5)), 1e-3)
    stresses, states = out
    assert stresses.shape == (3, 4) and states.shape == (3, 3)
    assert out.state_names == ["plastic_shear_strain", "plastic_volumetric_strain", "plastic_work"]


@pytest.mark.parametrize("phi", [20.0, 25.0, 35.0])
@pytest.mark.parametrize("kind", ["triaxial", "biaxial"])
def test_drained_compression_fails_at_mohr_coulomb_ratio(phi, kind):
    r = drained_triaxial(mc(phi), confining=1e3, axial_strain=0.02, steps=200, kind=kind)
    np.testing.assert_allclose(r.lateral_stress, 1e3, rtol=1e-9)  # drained: constant confinement
    ratio = r.axial_stress / r.lateral_stress
    k = yield_ratio(phi)
    assert k == pytest.approx((1 + math.sin(math.radians(phi))) / (1 - math.sin(math.radians(phi))))
    assert ratio.max() == pytest.approx(k, rel=1e-9)  # never above the failure ratio
    assert ratio[-1] == pytest.approx(k, rel=1e-9)  # perfectly plastic: stays on it
    assert r.state("plastic_shear_strain")[-1] > 0.0
    # before failure the ratio follows elasticity: dσ_a/dε_a = E (triaxial), E/(1-ν²) (biaxial)
    modulus = E if kind == "triaxial" else E / (1 - NU**2)
    assert (r.axial_stress[1] - r.axial_stress[0]) / (r.axial_strain[1] - r.axial_strain[0]) == pytest.approx(
        modulus, rel=1e-6)


def test_zero_dilation_no_plastic_volume_change_at_plane_return():
    r = drained_triaxial(mc(25.0, 0.0), confining=1e3, axial_strain=0.02, steps=200, kind="biaxial")
    # the plane return: σ33 strictly between the other two principal stresses
    s = -r.stresses[-1]
    assert s[0] < s[2] < s[1]
    plastic = r.state("plastic_shear_strain") > 0
    assert plastic[-1] and plastic.sum() > 50
    assert np.max(np.abs(r.state("plastic_volumetric_strain"))) < 1e-12
    ev = r.volumetric_strain[plastic]
    assert np.ptp(ev) < 1e-9  # no volume change once flowing at constant stress
    # the check is sensitive: ψ = 10° dilates
    d = drained_triaxial(mc(25.0, 10.0), confining=1e3, axial_strain=0.02, steps=200, kind="biaxial")
    assert d.state("plastic_volumetric_strain")[-1] > 1e-3
    assert d.volumetric_strain[-1] < d.volumetric_strain[100] - 1e-3


def test_material_is_validated_with_scenario_models():
    with pytest.raises(ScenarioError, match="youngs_modulus"):
        material_point(dict(mc(), youngs_modulus=-1.0), np.zeros((1, 5)), 1e-3)
    with pytest.raises(ScenarioError, match="dilation_angle"):
        validate_material(mc(25.0, 30.0))
    with pytest.raises(ScenarioError, match="frction_angle|friction_angle"):
        validate_material(dict(mc(), frction_angle=3))
    with pytest.raises(ValueError, match="shape"):
        material_point(mc(), np.zeros((2, 4)), 1e-3)
    with pytest.raises(ValueError, match="dt"):
        material_point(mc(), np.zeros((2, 5)), 0.0)


# --------------------------------------------------------------------------- retired keys

K_BULK = E / (3 * (1 - 2 * NU))


@pytest.mark.parametrize("key,value", [("recompaction", True), ("recompaction", False),
                                       ("cell_averaged_disconnection", True),
                                       ("inertial_friction_angle", 40.0)])
def test_a_retired_mohr_coulomb_key_is_refused_by_name(key, value):
    assert_named_error({**mc(), key: value}, key,
                       "is not a mohr_coulomb parameter (retired; see docs/studies/granular-variants.md)")


# --------------------------------------------------------------------------- apex, any principal order


def _stress(principal, in_plane_angle=0.0):
    """Stress [11, 22, 33, 12] with in-plane principal values principal[0], principal[1] (axes
    rotated by ``in_plane_angle``) and σ33 = principal[2]."""
    a, b, c = principal
    centre, half = 0.5 * (a + b), 0.5 * (a - b)
    return [centre + half * math.cos(2 * in_plane_angle), centre - half * math.cos(2 * in_plane_angle), c,
            half * math.sin(2 * in_plane_angle)]


def _return(material, stress):
    """One step without deformation: the return mapping of the trial ``stress`` itself."""
    return material_point(material, np.zeros((1, 5)), 1e-3, stress).stresses[0]


APEX_MATERIAL = dict(mc(phi=30.0, psi=0.0, c=1.0e4), tension_cutoff=1.0e9)  # cut-off clamped: none
APEX = 1.0e4 / math.tan(math.radians(30.0))  # c cot φ


@pytest.mark.parametrize("order", [(0, 1, 2), (2, 1, 0), (1, 0, 2), (0, 2, 1), (2, 0, 1), (1, 2, 0)])
@pytest.mark.parametrize("angle", [0.0, 0.3, 1.2])
def test_mohr_coulomb_apex_return_whatever_the_order_of_the_principal_stresses(order, angle):
    """A trial beyond the apex (all three principal stresses above c cot φ) returns to the apex
    (c cot φ, c cot φ, c cot φ), whichever of σ11, σ22, σ33 holds the largest principal stress:
    (2, 1, 0) is the reversed order, the out-of-plane stress the largest."""
    principal = (3.0e4, 2.6e4, 2.2e4)
    trial = _stress([principal[i] for i in order], angle)
    np.testing.assert_allclose(_return(APEX_MATERIAL, trial), [APEX, APEX, APEX, 0.0], rtol=1e-12, atol=1e-6 * APEX)


@pytest.mark.parametrize("principal", [
    (3.0e4, 2.6e4, 2.2e4),  # apex
    (2.0e4, -1.0e5, -1.2e5),  # edge and plane returns around the apex
    (1.5e4, 1.4e4, -8.0e4),
    (-1.0e4, -1.5e4, -9.0e4),
])
@pytest.mark.parametrize("cutoff", [1.0e9, 5.0e3])
def test_mohr_coulomb_return_is_the_same_for_reversed_principal_stresses(principal, cutoff):
    """The return map is isotropic: reversing which component holds which principal stress
    reverses the returned stress (σ11 ↔ σ33 swapped), with or without a tension cut-off."""
    material = dict(mc(phi=30.0, psi=5.0, c=1.0e4), tension_cutoff=cutoff)
    forward = _return(material, _stress(principal))
    reversed_ = _return(material, _stress(principal[::-1]))
    np.testing.assert_allclose(reversed_[[2, 1, 0, 3]], forward, rtol=1e-12, atol=1e-9 * max(map(abs, principal)))
    assert not np.allclose(forward, _stress(principal))  # plastic: the trial was outside


# --------------------------------------------------------------------------- disconnection

def disconnecting(phi_c=0.55, **extra):
    return {**mc(), "critical_packing_fraction": phi_c, "grain_density": 2500.0, "experimental": True, **extra}


def test_disconnected_sand_is_stress_free_and_recompacts_without_rebound():
    # Isotropic stretch past J_c = (1550/2500)/0.55 = 1.127, then the same volume back.
    dt = 1e-3
    up = np.tile([0.5, 0.0, 0.0, 0.5, 0.5], (200, 1))  # J = (1 + 5e-4)^600 ≈ 1.35
    down = np.tile([-0.5, 0.0, 0.0, -0.5, -0.5], (200, 1))
    path = np.vstack([up, down])
    on = material_point(disconnecting(), path, dt, [-2e3, -2e3, -2e3, 0.0])
    assert on.state_names == ["plastic_shear_strain", "plastic_volumetric_strain", "disconnection_work", "plastic_work"]
    jc = 1550.0 / 2500.0 / 0.55
    J = np.cumprod((1.0 + path[:, 0] * dt) ** 3)  # the driver's F update: (1 ± L dt)³ per step
    np.testing.assert_array_equal(on.stresses[J > jc], 0.0)
    # Back at J ≈ 1 (compressed by ln(J_c) beyond the critical packing) the pressure is the
    # elastic K ln(J_c / J) of that compression only; the plain model holds K ln(J_max / J).
    p_on = -on.stresses[-1, :3].mean()
    assert p_on == pytest.approx(K_BULK * math.log(jc / J[-1]), rel=0.02)
    off = material_point(mc(), path, dt, [-2e3, -2e3, -2e3, 0.0])
    assert -off.stresses[-1, :3].mean() > 2.0 * p_on


@pytest.mark.parametrize("extra, field, message", [
    ({"critical_packing_fraction": 0.7}, "critical_packing_fraction", "(0, 0.62]"),
    ({"critical_packing_fraction": 0.0}, "critical_packing_fraction", "must be > 0"),
    ({"grain_density": 1500.0}, "grain_density", "must be > density = 1550"),
    ({"grain_density": None}, "grain_density", "is required with critical_packing_fraction"),
])
def test_disconnection_input_errors_name_the_field(extra, field, message):
    assert_named_error(disconnecting(**extra), field, message)


# --------------------------------------------------------------------------- Drucker–Prager


def dp(mu=math.tan(math.radians(27.4))):
    return dict(model="drucker_prager", density=1550.0, youngs_modulus=E, poisson_ratio=NU, friction=mu)


@pytest.mark.parametrize("rate", [0.1, 10.0])
def test_drucker_prager_simple_shear_flows_at_its_friction_at_any_rate(rate):
    # Simple shear (L12 = rate) from an isotropic pressure: τ = √(½ s:s) rises elastically to
    # μ p and stays there; p does not change (isochoric flow, no elastic volume change).
    p, mu = 800.0, math.tan(math.radians(27.4))
    steps = 2000
    dt = 0.02 / rate / steps  # a total shear of 0.02, 27 × the elastic strain μ p / G
    L = np.zeros((steps, 5))
    L[:, 1] = rate
    out = material_point(dp(mu), L, dt, [-p, -p, -p, 0.0])
    s = out.stresses
    pressure = -(s[:, 0] + s[:, 1] + s[:, 2]) / 3
    dev = s[:, :3] + pressure[:, None]
    tau = np.sqrt(0.5 * (dev ** 2).sum(axis=1) + s[:, 3] ** 2)
    np.testing.assert_allclose(pressure, p, rtol=1e-9)
    assert tau.max() == pytest.approx(mu * p, rel=1e-9)  # never above the cone
    np.testing.assert_allclose(tau[-steps // 2:], mu * p, rtol=1e-9)  # flowing on it
    work = out.state("plastic_work")
    assert np.all(np.diff(work) >= -1e-12) and work[-1] > 0.0


def test_drucker_prager_is_stress_free_in_tension_and_names_a_bad_friction():
    out = material_point(dp(), np.tile([1.0, 0.0, 0.0, 1.0, 1.0], (3, 1)), 1e-3, [-100.0, -100.0, -100.0, 10.0])
    np.testing.assert_array_equal(out.stresses, 0.0)
    for bad in (0.0, 1.0, -0.2):
        with pytest.raises(ScenarioError) as err:
            validate_material(dp(bad))
        assert "friction" in str(err.value)


def test_drucker_prager_disconnected_below_the_critical_packing_recompacts_without_rebound():
    # The Mohr–Coulomb disconnection path above, with Drucker–Prager: stress-free while J > J_c,
    # and back near J = 1 the pressure is the elastic K ln(J_c / J) of the compaction beyond J_c.
    dt = 1e-3
    path = np.vstack([np.tile([0.5, 0.0, 0.0, 0.5, 0.5], (200, 1)), np.tile([-0.5, 0.0, 0.0, -0.5, -0.5], (200, 1))])
    on = material_point({**dp(), "critical_packing_fraction": 0.55, "grain_density": 2500.0, "experimental": True}, path, dt,
                        [-2e3, -2e3, -2e3, 0.0])
    jc = 1550.0 / 2500.0 / 0.55
    J = np.cumprod((1.0 + path[:, 0] * dt) ** 3)
    np.testing.assert_array_equal(on.stresses[J > jc], 0.0)
    assert np.any(on.stresses[J <= jc] != 0.0)
    p_on = -on.stresses[-1, :3].mean()
    assert p_on == pytest.approx(K_BULK * math.log(jc / J[-1]), rel=0.02)
    # the plain cone re-loads from the start of the compression: far more pressure
    off = material_point(dp(), path, dt, [-2e3, -2e3, -2e3, 0.0])
    assert -off.stresses[-1, :3].mean() > 2.0 * p_on


@pytest.mark.parametrize("extra, field, message", [
    ({"critical_packing_fraction": 0.7, "grain_density": 2500.0}, "critical_packing_fraction", "(0, 0.62]"),
    ({"critical_packing_fraction": 0.55, "grain_density": 1500.0}, "grain_density", "must be > density = 1550"),
    ({"critical_packing_fraction": 0.55}, "grain_density", "is required with critical_packing_fraction"),
])
def test_drucker_prager_disconnection_input_errors_name_the_field(extra, field, message):
    assert_named_error({**dp(), "experimental": True, **extra}, field, message)


def jop_beads(**extra):
    """Drucker–Prager with Jop et al.'s glass-bead μ(I) (μ_s 0.3819, μ₂ 0.6435, I₀ 0.279)."""
    return {**dp(0.3819), "inertial_friction": 0.6435, "grain_diameter": 1.15e-3, "grain_density": 2500.0,
            "experimental": True, **extra}


@pytest.mark.parametrize("section", [False, True])
def test_drucker_prager_mu_of_i_simple_shear_flows_at_the_friction_of_its_inertial_number(section):
    # Simple shear at γ̇ = 60/s from p = 500 Pa: I = γ̇ d/√(p/ρ_s) = 0.154, τ/p → μ(I) = 0.4752,
    # the same in plane-strain shear with and without the Mohr–Coulomb section.
    p, rate, steps = 500.0, 60.0, 4000
    dt = 0.05 / rate / steps
    L = np.zeros((steps, 5))
    L[:, 1] = rate
    out = material_point(jop_beads(mohr_coulomb_section=section), L, dt, [-p, -p, -p, 0.0])
    s = out.stresses
    pressure = -(s[:, 0] + s[:, 1] + s[:, 2]) / 3
    dev = s[:, :3] + pressure[:, None]
    tau = np.sqrt(0.5 * (dev ** 2).sum(axis=1) + s[:, 3] ** 2)
    inertial = rate * 1.15e-3 / math.sqrt(p / 2500.0)
    mu = 0.3819 + (0.6435 - 0.3819) * inertial / (0.279 + inertial)
    np.testing.assert_allclose(tau[-steps // 2:] / pressure[-steps // 2:], mu, rtol=1e-6)
    np.testing.assert_allclose(out.state("inertial_number")[-1], inertial, rtol=1e-6)


@pytest.mark.parametrize("extra, field, message", [
    ({"inertial_friction": 0.3}, "inertial_friction", "must be >= friction = 0.3819"),
    ({"inertial_friction": 1.2, "mohr_coulomb_section": True}, "inertial_friction", "< 1 (it is sin phi_2"),
    ({"grain_diameter": None}, "grain_diameter", "is required with inertial_friction"),
    ({"grain_density": None}, "grain_density", "is required with inertial_friction"),
    ({"grain_density": 1000.0}, "grain_density", "must be >= density = 1550"),
    ({"inertial_number_scale": 0.0}, "inertial_number_scale", ""),
])
def test_drucker_prager_mu_of_i_input_errors_name_the_field(extra, field, message):
    assert_named_error(jop_beads(**extra), field, message)
    validate_material(jop_beads(inertial_friction=1.2))  # μ₂ ≥ 1 is allowed on the circle


# --------------------------------------------------------------------------- experimental options


@pytest.mark.parametrize("material, key, what", [
    (dict(dp(0.3819), inertial_friction=0.6435, grain_diameter=1.15e-3, grain_density=2500.0),
     "inertial_friction", "is experimental"),
    (dict(dp(), critical_packing_fraction=0.55, grain_density=2500.0), "critical_packing_fraction", "is experimental"),
    (dict(mc(), critical_packing_fraction=0.55, grain_density=2500.0), "critical_packing_fraction", "is experimental"),
    (dict(model="granular_fluidity", density=1550.0, youngs_modulus=E, poisson_ratio=NU), "model",
     "granular_fluidity is experimental"),
])
def test_an_experimental_option_is_refused_without_the_opt_in(material, key, what):
    message = f"{what} (measured, not validated): set experimental = true in [materials.material] to use it"
    with pytest.raises(ScenarioError) as info:
        validate_material(material)
    assert info.value.errors == [(key, message)]
    validate_material({**material, "experimental": True})  # accepted with it


def test_the_opt_in_must_be_a_boolean():
    assert_named_error({**dp(), "experimental": "yes"}, "experimental", "boolean")
