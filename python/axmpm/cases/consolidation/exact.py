"""Terzaghi's one-dimensional consolidation, closed form (Terzaghi 1943; Verruijt, *Soil
Mechanics*, ch. 15), with compressible pore water.

A layer of thickness H drained at its top (p = 0) and impermeable at its base carries a
surface load q applied at t = 0. The load is shared at once between the water and the skeleton
(undrained), u₀ = q (K_w/n)/(K_w/n + E_oed), then the excess pressure diffuses,
∂u/∂t = c_v ∂²u/∂z², with c_v = k / (γ_w (1/E_oed + n/K_w)) (the water's compressibility n/K_w
adds to the skeleton's 1/E_oed in the storage), z the depth below the drained top:

    u(z, t)/u₀ = Σ_m (2/M) sin(M z/H) exp(−M² T_v),   M = π(2m + 1)/2,   T_v = c_v t/H²,
    U(T_v) = 1 − Σ_m (2/M²) exp(−M² T_v)

(U, the mean degree of consolidation, is also the settlement's share of its final value).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["GAMMA_GRAVITY", "undrained_pressure", "consolidation_coefficient", "degree", "pressure",
           "time_factor_of_degree"]

#: g in γ_w = ρ_w g, the gravity the hydraulic conductivity is defined under (the engine's).
GAMMA_GRAVITY = 9.81
#: Terms of the series: at T_v ≥ 1e-4 the neglected terms are below 1e-12.
TERMS = 4000


def undrained_pressure(load: float, porosity: float, water_bulk_modulus: float, oedometer_modulus: float) -> float:
    """u₀ = q (K_w/n)/(K_w/n + E_oed)."""
    stiffness = water_bulk_modulus / porosity
    return load * stiffness / (stiffness + oedometer_modulus)


def consolidation_coefficient(conductivity: float, water_density: float, porosity: float,
                              water_bulk_modulus: float, oedometer_modulus: float) -> float:
    """c_v = k / (γ_w (1/E_oed + n/K_w)), m²/s."""
    return conductivity / (water_density * GAMMA_GRAVITY * (1.0 / oedometer_modulus + porosity / water_bulk_modulus))


def _m() -> np.ndarray:
    return math.pi * (2.0 * np.arange(TERMS) + 1.0) / 2.0


def degree(tv: float) -> float:
    """Mean degree of consolidation U(T_v)."""
    m = _m()
    return float(1.0 - np.sum(2.0 / m**2 * np.exp(-(m**2) * tv)))


def pressure(depth_ratio: np.ndarray | float, tv: float) -> np.ndarray:
    """u/u₀ at z/H = ``depth_ratio`` below the drained top."""
    m = _m()
    z = np.atleast_1d(np.asarray(depth_ratio, dtype=float))
    return np.sum(2.0 / m * np.sin(np.outer(z, m)) * np.exp(-(m**2) * tv), axis=1)


def time_factor_of_degree(u: float) -> float:
    """T_v at which U = ``u`` (bisection on the monotone U(T_v))."""
    lo, hi = 1e-8, 10.0
    for _ in range(200):
        mid = math.sqrt(lo * hi)
        if degree(mid) < u:
            lo = mid
        else:
            hi = mid
    return math.sqrt(lo * hi)
