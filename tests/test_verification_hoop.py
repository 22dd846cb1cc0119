"""Verification with ν > 0 in axisymmetry, where the hoop force matters (docs/physics.md §2, §4).

A linear-elastic column (ν = 0.3) under self-weight with rollers on its lateral faces is in
uniaxial strain: u_r = 0, σ_zz = −ρ0 g (H − z), σ_rr = σ_θθ = ν/(1 − ν) σ_zz and
u_z = −(ρ0 g/M)(H z − z²/2), M = E(1 − ν)/((1 + ν)(1 − 2ν)) the P-wave modulus. In axisymmetry the
radial equation balances ∂σ_rr/∂r against the hoop term (σ_rr − σ_θθ)/r: each node's radial
internal force pairs −∫ σ_rr ∂N/∂r dV with −∫ σ_θθ N/r dV, which cancel only together (for
ν = 0 both vanish, so the ν = 0 columns of ``axmpm verify`` cannot see the hoop force). Without
the hoop force every interior node would be pushed radially by ≈ σ_θθ A/r and the column would
bulge: the radial displacement, the equality σ_rr = σ_θθ and the lateral stress catch it.
Small strain (ρ0 g H/E = 0.01), cpGIMP, 32 cells along and 4 across.

Tolerances: the stresses within 2 % (relative L2 over the particles; the cell-scale error of
the particle stresses is ≈ 1.3 % here, as in plane strain), u_z within 1 %, |u_r| below 1e-6 of
the largest |u_z| and σ_rr = σ_θθ to 1e-6 of the largest |σ_zz|.
"""

from __future__ import annotations

import numpy as np
import pytest

import axmpm
from axmpm.cases.column_1d import column_scenario

RHO, G, H, E, NU = 1000.0, 10.0, 1.0, 1.0e6, 0.3
M = E * (1 - NU) / ((1 + NU) * (1 - 2 * NU))
K0 = NU / (1 - NU)
CELLS_ALONG, CELLS_ACROSS = 32, 4


def _l2(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.linalg.norm(a - b) / np.linalg.norm(b))


@pytest.fixture(scope="module", params=[0, 20], ids=["on_the_axis", "offset_20_widths"])
def column(request, tmp_path_factory: pytest.TempPathFactory):
    widths = request.param
    offset = widths * CELLS_ACROSS * H / CELLS_ALONG
    scenario = column_scenario("axisymmetric", "cpgimp", "compression", cells_along=CELLS_ALONG,
                               cells_across=CELLS_ACROSS, offset=offset, height=H, density=RHO, gravity=G,
                               youngs_modulus=E, material_model="linear_elastic", poisson_ratio=NU)
    assert scenario.materials["column"].poisson_ratio == NU
    out = tmp_path_factory.mktemp("hoop") / f"column_{widths}"
    summary = axmpm.run(scenario, out, threads=1, progress=False)
    assert summary["status"] == "completed", summary["message"]
    return axmpm.load_run(out).last


def test_lateral_and_hoop_stress_match_uniaxial_strain(column) -> None:
    z = np.asarray(column.X0)[:, 1]
    szz = -RHO * G * (H - z)
    s = np.asarray(column.stress)  # [rr, zz, θθ, rz]
    assert _l2(s[:, 1], szz) < 0.02
    assert _l2(s[:, 0], K0 * szz) < 0.02
    assert _l2(s[:, 2], K0 * szz) < 0.02
    assert np.max(np.abs(s[:, 0] - s[:, 2])) < 1e-6 * np.max(np.abs(szz))
    assert np.max(np.abs(s[:, 3])) < 1e-6 * np.max(np.abs(szz))


def test_no_radial_motion_and_exact_settlement(column) -> None:
    z = np.asarray(column.X0)[:, 1]
    u = np.asarray(column.x) - np.asarray(column.X0)
    uz = -(RHO * G / M) * (H * z - 0.5 * z * z)
    assert _l2(u[:, 1], uz) < 0.01
    assert np.max(np.abs(u[:, 0])) < 1e-6 * np.max(np.abs(uz))
