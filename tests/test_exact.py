"""The exact 1D column solution (docs/physics.md §4) checked against independent computations."""

from __future__ import annotations

import numpy as np
import pytest

from axmpm.cases.column_1d import exact

H, RHO, G = 1.0, 1000.0, 10.0
MODES = ["compression", "tension"]


def modulus(s0: float) -> float:
    return RHO * G * H / s0


def cumulative_trapezoid(y: np.ndarray, x: np.ndarray) -> np.ndarray:
    return np.concatenate([[0.0], np.cumsum(0.5 * (y[1:] + y[:-1]) * np.diff(x))])


def test_stress_is_the_weight_exactly() -> None:
    X = np.linspace(0, H, 101)
    for E in (2e4, 1e6):
        np.testing.assert_array_equal(exact.vertical_stress(X, H, RHO, G, E, "compression"), -RHO * G * (H - X))
        np.testing.assert_array_equal(exact.vertical_stress(X, H, RHO, G, E, "tension"), RHO * G * X)


@pytest.mark.parametrize("mode", MODES)
@pytest.mark.parametrize("s0", [0.01, 0.5, 2.0])
def test_stretch_satisfies_the_neo_hookean_law(mode: str, s0: float) -> None:
    E = modulus(s0)
    X = np.linspace(0, H, 201)
    stretch = exact.vertical_stretch(X, H, RHO, G, E, mode)
    np.testing.assert_allclose(
        exact.neo_hookean_1d_stress(stretch, E), exact.vertical_stress(X, H, RHO, G, E, mode), rtol=1e-12, atol=1e-9
    )


def test_seed_case_stretches() -> None:
    # s0 = 0.5: 38 % shortening at the base in compression, 62 % stretch at the top in tension.
    E = modulus(0.5)
    assert exact.vertical_stretch(0.0, H, RHO, G, E, "compression") == pytest.approx(0.618034, abs=1e-6)
    assert exact.vertical_stretch(H, H, RHO, G, E, "tension") == pytest.approx(1.618034, abs=1e-6)


@pytest.mark.parametrize("s0", [0.01, 0.5, 2.0])
def test_compression_positions_integrate_the_stretch(s0: float) -> None:
    E = modulus(s0)
    X = np.linspace(0, H, 20001)
    x_numeric = cumulative_trapezoid(exact.vertical_stretch(X, H, RHO, G, E, "compression"), X)
    x_exact = exact.vertical_position(X, H, RHO, G, E, "compression")
    assert x_exact[0] == pytest.approx(0.0, abs=1e-14)  # the base stays put
    np.testing.assert_allclose(x_exact, x_numeric, atol=1e-8 * H)


@pytest.mark.parametrize("s0", [0.01, 0.5, 2.0])
def test_tension_positions_integrate_the_stretch(s0: float) -> None:
    E = modulus(s0)
    X = np.linspace(0, H, 20001)
    stretch = exact.vertical_stretch(X, H, RHO, G, E, "tension")
    from_bottom = cumulative_trapezoid(stretch, X)
    x_numeric = H - (from_bottom[-1] - from_bottom)  # integrate from the fixed top downwards
    x_exact = exact.vertical_position(X, H, RHO, G, E, "tension")
    assert x_exact[-1] == pytest.approx(H, abs=1e-14)  # the top stays put
    np.testing.assert_allclose(x_exact, x_numeric, atol=1e-8 * H)


@pytest.mark.parametrize("mode", MODES)
def test_small_strain_limit(mode: str) -> None:
    X = np.linspace(0, H, 51)
    previous = None
    for s0 in (1e-2, 1e-3, 1e-4):
        E = modulus(s0)
        u = exact.vertical_displacement(X, H, RHO, G, E, mode)
        u_lin = exact.small_strain_displacement(X, H, RHO, G, E, mode)
        rel = np.max(np.abs(u - u_lin)) / np.max(np.abs(u_lin))
        assert rel < s0  # the large-deformation correction is O(s0)
        if previous is not None:
            assert rel < previous / 5  # and vanishes linearly with s0
        previous = rel


def test_small_strain_formulas() -> None:
    E = modulus(0.01)
    k = RHO * G / E
    assert exact.small_strain_displacement(H, H, RHO, G, E, "compression") == pytest.approx(-k * H**2 / 2)
    assert exact.small_strain_displacement(0.0, H, RHO, G, E, "tension") == pytest.approx(-k * H**2 / 2)
    assert exact.small_strain_displacement(H, H, RHO, G, E, "tension") == 0.0


def test_bad_mode() -> None:
    with pytest.raises(ValueError, match="mode"):
        exact.vertical_stress(0.5, H, RHO, G, 1e6, "shear")  # type: ignore[arg-type]
