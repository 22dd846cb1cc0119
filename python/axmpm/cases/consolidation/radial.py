"""Radial consolidation, closed forms: Cryer's sphere (Cryer 1963) and de Leeuw's cylinder
(de Leeuw 1965), for a linear elastic skeleton of incompressible grains saturated with
compressible water (Biot coefficient 1, Biot modulus M = K_w/n), in the constants of
:class:`.mandel.MandelMaterial` (K, G, M, the consolidation coefficient c).

Both bodies are drained at their surface r = R from t = 0 and loaded there by a total radial
pressure q (the sphere all round; the cylinder radially, between rigid, frictionless,
impermeable plates that hold its length, ε_z = 0). The load is carried undrained at first,
with a uniform pore pressure p₀; then the surface drains. Equilibrium of an irrotational
displacement field gives E_c ε_v = p + C(t) (E_c = K + 4G/3 the constrained modulus, ε_v the
volumetric strain), the surface's load fixes C(t) through the mean pressure ⟨p⟩ over the body,
and the storage equation becomes

    ∂p/∂t + η d⟨p⟩/dt = c ∇²p,   c = k / (γ_w (1/M + 1/E_c)),

η the coupling of the two (sphere: η = 4GM/(3K(E_c + M)); cylinder: η = GM/((K + G/3)(E_c + M))).
The Laplace transform of this equation gives the series below (docs/physics.md §10,
"Verification: Cryer's sphere and de Leeuw's cylinder"); T = c t/R², ρ = r/R.

Sphere (the form of Verruijt 2013, which Cheng 2016, §7.10, writes in ν and ν_u):
    p₀ = B q,   η_V = [(1 − ν)/(1 − 2ν)] (1 + K/M),   (1 − η_V ξ²/2) tan ξ = ξ,
    p/p₀ = η_V Σ_j [sin ξ_j − sin(ρ ξ_j)/ρ] / [(η_V − 1) sin ξ_j + (η_V/2) ξ_j cos ξ_j] exp(−ξ_j² T),
    (at the centre sin(ρξ)/ρ → ξ).

Cylinder (Verruijt 2013):
    p₀ = M q/(K + G/3 + M),   m = [(1 − ν)/(2(1 − 2ν))] (1 + (K + G/3)/M),   2m ξ J₀(ξ) = J₁(ξ),
    p/p₀ = Σ_j [J₀(ξ_j) − J₀(ρ ξ_j)] / [(1 − m ξ_j² − 1/(4m)) J₀(ξ_j)] exp(−ξ_j² T).

The centre's pressure first rises above p₀ (the Mandel–Cryer effect): the drained outer shell
contracts and squeezes the still undrained core.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = ["SPHERE", "CYLINDER", "sphere_coupling", "cylinder_coupling", "initial_pressure", "roots", "pressure",
           "centre_pressure", "initial_effective_stress"]

SPHERE = "sphere"
CYLINDER = "cylinder"
#: Terms of the series: the j-th root is about jπ, so at c t/R² ≥ 1e-4 the neglected terms are
#: below exp(−π² 4e6 · 1e-4) ≈ 1e-170 of p₀ (and the short-time sum converges like Σ exp(−j² π² T)).
TERMS = 2000


def _check(shape: str) -> None:
    if shape not in (SPHERE, CYLINDER):
        raise ValueError(f"shape must be {SPHERE!r} or {CYLINDER!r} (got {shape!r})")


def sphere_coupling(material: Any) -> float:
    """η_V = [(1 − ν)/(1 − 2ν)] (1 + K/M) = E_c (K + M)/(2 G M)."""
    k, g, m = material.bulk_modulus, material.shear_modulus, material.biot_modulus
    return (k + 4.0 * g / 3.0) * (k + m) / (2.0 * g * m)


def cylinder_coupling(material: Any) -> float:
    """m = E_c (K + G/3 + M)/(4 G M) = [(1 − ν)/(2(1 − 2ν))] (1 + (K + G/3)/M)."""
    k, g, m = material.bulk_modulus, material.shear_modulus, material.biot_modulus
    return (k + 4.0 * g / 3.0) * (k + g / 3.0 + m) / (4.0 * g * m)


def initial_pressure(shape: str, load: float, material: Any) -> float:
    """The undrained pore pressure p₀ under the surface's total pressure ``load``: B q for the
    sphere (isotropic load), M q/(K + G/3 + M) for the cylinder (radial load at ε_z = 0)."""
    _check(shape)
    k, g, m = material.bulk_modulus, material.shear_modulus, material.biot_modulus
    if shape == SPHERE:
        return load * m / (m + k)
    return load * m / (k + g / 3.0 + m)


def initial_effective_stress(shape: str, load: float, material: Any) -> tuple[float, float, float]:
    """(σ′_rr, σ′_zz, σ′_θθ) of the undrained state minus the drained one (tension positive),
    the initial effective stress of the drained-surface perturbation (docs/physics.md §10): p₀ in
    every direction for the sphere; p₀ radially and in the hoop direction and p₀ λ/(λ + G) axially
    for the cylinder (λ = K − 2G/3; its total axial stress −p₀ G/(λ + G) is the plates' reaction)."""
    p0 = initial_pressure(shape, load, material)
    if shape == SPHERE:
        return p0, p0, p0
    lam = material.bulk_modulus - 2.0 * material.shear_modulus / 3.0
    return p0, p0 * lam / (lam + material.shear_modulus), p0


def roots(shape: str, coupling: float, terms: int = TERMS) -> np.ndarray:
    """The first ``terms`` positive roots of the characteristic equation, by bisection on
    brackets holding one root each. Sphere: f(ξ) = (1 − η_V ξ²/2) sin ξ − ξ cos ξ, negative near 0
    (f ≈ (1/3 − η_V/2) ξ³, η_V ≥ 1) and −jπ cos(jπ) at ξ = jπ: one root in each (jπ, (j + 1)π).
    Cylinder: g(ξ) = 2m ξ J₀(ξ) − J₁(ξ), positive near 0 (m > 1/4) and 2m ξ J₀ of alternating
    sign at the zeros of J₁ (the extrema of J₀): one root below the first zero, then one between
    consecutive zeros."""
    _check(shape)
    if shape == SPHERE:
        eta = coupling

        def f(x: np.ndarray) -> np.ndarray:
            return (1.0 - 0.5 * eta * x * x) * np.sin(x) - x * np.cos(x)

        j = np.arange(terms, dtype=float)
        lo, hi = np.maximum(j * math.pi, 1e-3), (j + 1.0) * math.pi
    else:
        from scipy.special import j0, j1, jn_zeros

        m = coupling

        def f(x: np.ndarray) -> np.ndarray:
            return 2.0 * m * x * j0(x) - j1(x)

        zeros = jn_zeros(1, terms)
        lo, hi = np.concatenate([[1e-6], zeros[:-1]]), zeros
    f_lo = f(lo)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        same = np.sign(f(mid)) == np.sign(f_lo)
        lo = np.where(same, mid, lo)
        hi = np.where(same, hi, mid)
    return 0.5 * (lo + hi)


def _coupling(shape: str, material: Any) -> float:
    return sphere_coupling(material) if shape == SPHERE else cylinder_coupling(material)


def pressure(shape: str, radius_ratio: float, time_factor: np.ndarray | float, material: Any,
             terms: int = TERMS) -> np.ndarray:
    """p/p₀ at r/R = ``radius_ratio`` and c t/R² = ``time_factor`` (module doc)."""
    _check(shape)
    coupling = _coupling(shape, material)
    xi = roots(shape, coupling, terms)
    rho = float(radius_ratio)
    t = np.atleast_1d(np.asarray(time_factor, dtype=float))
    if shape == SPHERE:
        eta = coupling
        inner = xi if rho == 0.0 else np.sin(rho * xi) / rho
        weight = eta * (np.sin(xi) - inner) / ((eta - 1.0) * np.sin(xi) + 0.5 * eta * xi * np.cos(xi))
    else:
        from scipy.special import j0

        m = coupling
        weight = (j0(xi) - j0(rho * xi)) / ((1.0 - m * xi**2 - 1.0 / (4.0 * m)) * j0(xi))
    return np.sum(weight[None, :] * np.exp(-np.outer(t, xi**2)), axis=1)


def centre_pressure(shape: str, time_factor: np.ndarray | float, material: Any) -> np.ndarray:
    """p/p₀ at the centre r = 0."""
    return pressure(shape, 0.0, time_factor, material)
