"""Exact static solution of a 1D column under self-weight (docs/physics.md §4).

Uniaxial strain (lateral faces on rollers), compressible neo-Hookean law with ν = 0
(μ = E/2, λ = 0), which along the column reduces to

    σ = (E/2)(λ_s − 1/λ_s),          λ_s the axial stretch,

with zero lateral stress. The cross-section does not change, so Cauchy stress equals
nominal stress and equilibrium alone fixes σ(X). Notation: X the initial height above the
bottom of the column, H its initial length, ρ0 the initial density, g > 0 the magnitude
of gravity (acting downwards), s = ρ0 g (·)/E the dimensionless load.

* ``"compression"`` (base fixed at X = 0, top free): σ(X) = −ρ0 g (H − X),
  λ_s = −s + √(1+s²) with s = ρ0 g (H − X)/E, and the current height above the base
  x(X) = (E/(ρ0 g)) [G(s0) − G(s(X))], s0 = ρ0 g H/E, G(t) = ½(t√(1+t²) + asinh t) − t²/2.
* ``"tension"`` (top fixed at X = H, hanging): σ(X) = +ρ0 g X, λ_s = s + √(1+s²) with
  s = ρ0 g X/E; x(X) = H − (E/(ρ0 g)) [K(s_H) − K(s(X))], K(t) = t²/2 + ½(t√(1+t²) + asinh t),
  the integral of the stretch from X to the fixed top.
* Small-strain limit (linear elasticity, σ = E ε): compression u = −(ρ0 g/E)(H X − X²/2);
  tension u = −(ρ0 g/(2E))(H² − X²).

All functions are vectorised over X (m) and return SI values, tension positive.
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

Mode = Literal["compression", "tension"]
__all__ = [
    "Mode",
    "vertical_stress",
    "vertical_stretch",
    "vertical_position",
    "vertical_displacement",
    "small_strain_displacement",
    "neo_hookean_1d_stress",
]


def _check_mode(mode: str) -> None:
    if mode not in ("compression", "tension"):
        raise ValueError(f"mode must be 'compression' or 'tension' (got {mode!r})")


def _load(X: NDArray[np.float64], H: float, rho0: float, g: float, E: float, mode: str):
    """Dimensionless load s(X) = ρ0 g ℓ/E, ℓ the length of column hanging on / resting on X."""
    _check_mode(mode)
    length = (H - X) if mode == "compression" else X
    return rho0 * g * length / E


def neo_hookean_1d_stress(stretch: ArrayLike, E: float) -> NDArray[np.float64]:
    """Axial Cauchy stress of the ν = 0 neo-Hookean law in uniaxial strain: (E/2)(λ − 1/λ)."""
    lam = np.asarray(stretch, dtype=float)
    return 0.5 * E * (lam - 1.0 / lam)


def vertical_stress(X: ArrayLike, H: float, rho0: float, g: float, E: float, mode: Mode) -> NDArray[np.float64]:
    """Axial (vertical) Cauchy stress at initial height X: −ρ0 g (H−X) or +ρ0 g X (exact, any E)."""
    X = np.asarray(X, dtype=float)
    _check_mode(mode)
    return -rho0 * g * (H - X) if mode == "compression" else rho0 * g * X


def vertical_stretch(X: ArrayLike, H: float, rho0: float, g: float, E: float, mode: Mode) -> NDArray[np.float64]:
    """Axial stretch λ_s(X) = ∓s + √(1+s²) that makes (E/2)(λ − 1/λ) equal the stress."""
    X = np.asarray(X, dtype=float)
    s = _load(X, H, rho0, g, E, mode)
    root = np.sqrt(1.0 + s * s)
    return -s + root if mode == "compression" else s + root


def _G(t: NDArray[np.float64]) -> NDArray[np.float64]:
    """∫ (√(1+t²) − t) dt: antiderivative of the compression stretch."""
    return 0.5 * (t * np.sqrt(1.0 + t * t) + np.arcsinh(t)) - 0.5 * t * t


def _K(t: NDArray[np.float64]) -> NDArray[np.float64]:
    """∫ (t + √(1+t²)) dt: antiderivative of the tension stretch."""
    return 0.5 * t * t + 0.5 * (t * np.sqrt(1.0 + t * t) + np.arcsinh(t))


def vertical_position(X: ArrayLike, H: float, rho0: float, g: float, E: float, mode: Mode) -> NDArray[np.float64]:
    """Current height x(X) of the material point initially at X, both measured from the
    column's initial bottom (the fixed base in compression; the top X = H stays put in tension)."""
    X = np.asarray(X, dtype=float)
    _check_mode(mode)
    scale = E / (rho0 * g)
    if mode == "compression":
        s0 = rho0 * g * H / E
        return scale * (_G(np.asarray(s0)) - _G(_load(X, H, rho0, g, E, mode)))
    sH = rho0 * g * H / E
    return H - scale * (_K(np.asarray(sH)) - _K(_load(X, H, rho0, g, E, mode)))


def vertical_displacement(X: ArrayLike, H: float, rho0: float, g: float, E: float, mode: Mode) -> NDArray[np.float64]:
    """Vertical displacement u(X) = x(X) − X (negative: downwards)."""
    X = np.asarray(X, dtype=float)
    return vertical_position(X, H, rho0, g, E, mode) - X


def small_strain_displacement(X: ArrayLike, H: float, rho0: float, g: float, E: float, mode: Mode) -> NDArray[np.float64]:
    """Linear-elastic limit of :func:`vertical_displacement` (σ = E ε, ν = 0)."""
    X = np.asarray(X, dtype=float)
    _check_mode(mode)
    k = rho0 * g / E
    if mode == "compression":
        return -k * (H * X - 0.5 * X * X)
    return -0.5 * k * (H * H - X * X)
