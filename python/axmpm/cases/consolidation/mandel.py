"""Mandel's problem, closed form (Mandel 1953; Cheng & Detournay 1988, IJNAMG 12; Abousleiman
et al. 1996), for a skeleton of incompressible grains saturated with compressible water.

A long specimen of width 2a (plane strain) between two rigid, frictionless, impermeable plates
carries a force 2F per metre from t = 0; its sides x = ±a are free and drained. At once the load
is carried undrained, with the pore pressure p₀ = F B (1 + ν_u)/(3a) (B Skempton's coefficient,
ν_u the undrained Poisson ratio); then the water drains through the sides. The pressure at
distance x from the centre is

    p(x, t) = 2 p₀ Σ_n [sin α_n/(α_n − sin α_n cos α_n)] (cos(α_n x/a) − cos α_n) exp(−α_n² c t/a²),
    tan α_n = [(1 − ν)/(ν_u − ν)] α_n,

c the consolidation coefficient. The centre's pressure first rises above p₀ (the Mandel–Cryer
effect: the drained sides soften, the plate's load moves to the stiffer undrained core) before
it decays. With incompressible grains (Biot's coefficient 1, Biot modulus M = K_w/n), for a
skeleton of drained bulk modulus K and shear modulus G:

    K_u = K + K_w/n,   B = (K_w/n)/(K_w/n + K),
    ν_u = (3K_u − 2G)/(2(3K_u + G)),   c = k/(γ_w (1/(K + 4G/3) + n/K_w)).
"""

from __future__ import annotations

import math

import numpy as np

from .exact import GAMMA_GRAVITY

__all__ = ["MandelMaterial", "roots", "centre_pressure", "pressure"]

#: Terms of the series: at c t/a² ≥ 1e-4 the neglected terms are below 1e-10 of p₀.
TERMS = 2000


class MandelMaterial:
    """The constants of the closed form for a linear elastic skeleton (E, ν) saturated with water
    (n, K_w, ρ_w, k)."""

    def __init__(self, youngs_modulus: float, poisson_ratio: float, porosity: float, water_bulk_modulus: float,
                 water_density: float, conductivity: float):
        e, nu = youngs_modulus, poisson_ratio
        self.poisson_ratio = nu
        self.bulk_modulus = e / (3.0 * (1.0 - 2.0 * nu))
        self.shear_modulus = e / (2.0 * (1.0 + nu))
        self.biot_modulus = biot_modulus = water_bulk_modulus / porosity
        k_u = self.bulk_modulus + biot_modulus
        self.skempton = biot_modulus / (biot_modulus + self.bulk_modulus)
        g = self.shear_modulus
        self.undrained_poisson_ratio = (3.0 * k_u - 2.0 * g) / (2.0 * (3.0 * k_u + g))
        constrained = self.bulk_modulus + 4.0 * g / 3.0
        self.consolidation_coefficient = conductivity / (
            water_density * GAMMA_GRAVITY * (1.0 / constrained + porosity / water_bulk_modulus))

    def initial_pressure(self, mean_vertical_stress: float) -> float:
        """p₀ = F B (1 + ν_u)/(3a) for the plate's mean pressure F/a."""
        return mean_vertical_stress * self.skempton * (1.0 + self.undrained_poisson_ratio) / 3.0


def roots(poisson_ratio: float, undrained_poisson_ratio: float, terms: int = TERMS) -> np.ndarray:
    """The first ``terms`` positive roots of tan α = C α, C = (1 − ν)/(ν_u − ν) > 1: one in
    (0, π/2), then one in each ((n − ½)π, (n + ½)π); bisection on each bracket."""
    c = (1.0 - poisson_ratio) / (undrained_poisson_ratio - poisson_ratio)
    n = np.arange(terms, dtype=float)
    eps = 1e-12
    lo = np.where(n == 0, eps, (n - 0.5) * math.pi + eps)
    hi = (n + 0.5) * math.pi - eps
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        negative = np.tan(mid) - c * mid < 0.0
        lo = np.where(negative, mid, lo)
        hi = np.where(negative, hi, mid)
    return 0.5 * (lo + hi)


def pressure(x_ratio: float, time_factor: np.ndarray | float, material: MandelMaterial) -> np.ndarray:
    """p/p₀ at x/a = ``x_ratio`` and c t/a² = ``time_factor`` (module doc)."""
    alpha = roots(material.poisson_ratio, material.undrained_poisson_ratio)
    t = np.atleast_1d(np.asarray(time_factor, dtype=float))
    weight = np.sin(alpha) / (alpha - np.sin(alpha) * np.cos(alpha)) * (np.cos(alpha * x_ratio) - np.cos(alpha))
    return 2.0 * np.sum(weight[None, :] * np.exp(-np.outer(t, alpha**2)), axis=1)


def centre_pressure(time_factor: np.ndarray | float, material: MandelMaterial) -> np.ndarray:
    """p/p₀ at the centre x = 0."""
    return pressure(0.0, time_factor, material)


def field_errors(positions: np.ndarray, pore_pressure: np.ndarray, cell_size: float, half_width: float,
                 time_factor: float, material: MandelMaterial, p0: float) -> tuple[float, float]:
    """The pressure field of one frame against the closed form, per background cell (the
    storage strain is averaged per cell, so the cell is the pressure's unit): the worst
    |⟨p⟩_cell − p_exact(x_cell)|/p₀ over the cells, with x_cell the cell's centre, and the
    largest spread (max − min)/p₀ of ⟨p⟩_cell down one column of cells, where the exact field
    does not change (p depends on x only): a checkerboard would show there."""
    x = np.asarray(positions, dtype=float)
    p = np.asarray(pore_pressure, dtype=float)
    i = np.floor(x[:, 0] / cell_size).astype(int)
    j = np.floor(x[:, 1] / cell_size).astype(int)
    cells = np.unique(np.stack([i, j], axis=1), axis=0)
    means = np.array([p[(i == ci) & (j == cj)].mean() for ci, cj in cells]) / p0
    exact = np.array([pressure((ci + 0.5) * cell_size / half_width, time_factor, material)[0] for ci, _ in cells])
    spread = max(float(np.ptp(means[cells[:, 0] == ci])) for ci in np.unique(cells[:, 0]))
    return float(np.max(np.abs(means - exact))), spread
