"""Drive one material point of an engine material model (``axmpm._core.material_response``).

The material dict is validated with the scenario's pydantic material models (the same keys
and ranges as ``[materials.NAME]`` in a scenario file), so a bad material raises
:class:`~axmpm.errors.ScenarioError` with dotted keys, not an engine error.

Stress components are ordered [11, 22, 33, 12] (plane strain: [xx, yy, zz, xy];
axisymmetric: [rr, zz, θθ, rz]), tension positive, Pa. Velocity gradients are
[L11, L12, L21, L22, L33] in 1/s, each applied for ``dt``.

:func:`drained_triaxial` builds a stress-controlled lateral boundary on top of the
strain-driven engine: each step solves for the lateral strain rate that keeps the lateral
stress at the confining pressure (the response is piecewise linear in that rate, so a secant
iteration converges in two or three evaluations). The material models are rate
formulations (hypoelastic, Jaumann), so driving one step at a time from the previous
stress is exact; only the accumulated state variables are summed here.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray
from pydantic import TypeAdapter, ValidationError

from .engine import core
from .errors import ScenarioError
from .scenario import Material, MATERIAL_MODELS, convert_errors
from .scenario.materials import engine_key_errors

__all__ = ["material_point", "MaterialPointResponse", "validate_material", "drained_triaxial",
           "TriaxialResult", "yield_ratio"]

_ADAPTER: TypeAdapter[Any] = TypeAdapter(Material)


def _strip_tag(key: str) -> str:
    """Drop the discriminator tag pydantic puts in front of a field (``mohr_coulomb.cohesion``)."""
    for model in MATERIAL_MODELS:
        if key.startswith(model + "."):
            return key[len(model) + 1:]
    return key


def validate_material(material: dict[str, Any] | Any) -> Any:
    """A validated material model (LinearElastic, NeoHookean or MohrCoulomb)."""
    if not isinstance(material, dict):
        if hasattr(material, "model_dump"):
            return material
        raise ScenarioError([("material", f"must be a table of material keys (got {material!r})")], "material")
    try:
        mat = _ADAPTER.validate_python(material)
    except ValidationError as exc:
        errors = [(_strip_tag(key), msg) for key, msg in convert_errors(exc)]
        raise ScenarioError(errors, "material") from None
    # the model's own cross checks (ψ ≤ φ, the μ(I) keys) and the engine's refusal of
    # experimental options without the opt-in, keys without a prefix
    errors = mat.cross_errors("") + [(key.removeprefix("materials.material."), message)
                                     for key, message in engine_key_errors("material", mat.model_dump(mode="json"))]
    if errors:
        raise ScenarioError(errors, "material")
    return mat


class MaterialPointResponse(tuple):
    """``(stresses (S, 4), states (S, k))``, unpackable as a pair; ``state_names`` lists the
    state columns and :meth:`state` picks one by name."""

    state_names: list[str]

    def __new__(cls, stresses: NDArray[np.float64], states: NDArray[np.float64],
                state_names: Sequence[str]) -> "MaterialPointResponse":
        obj = super().__new__(cls, (stresses, states))
        obj.state_names = list(state_names)
        return obj

    @property
    def stresses(self) -> NDArray[np.float64]:
        return self[0]

    @property
    def states(self) -> NDArray[np.float64]:
        return self[1]

    def state(self, name: str) -> NDArray[np.float64]:
        try:
            return self[1][:, self.state_names.index(name)]
        except ValueError:
            raise KeyError(f"no state {name!r}; states: {self.state_names}") from None


def material_point(
    material: dict[str, Any],
    velocity_gradients: ArrayLike,
    dt: float,
    initial_stress: Sequence[float] = (0.0, 0.0, 0.0, 0.0),
) -> MaterialPointResponse:
    """Drive one material point through ``velocity_gradients`` (S, 5), each for ``dt`` seconds.

    Returns the stress after every step (S, 4) and the state variables (S, k) (e.g.
    ``plastic_shear_strain``, ``plastic_volumetric_strain`` for mohr_coulomb).
    """
    mat = validate_material(material)
    L = np.ascontiguousarray(np.asarray(velocity_gradients, dtype=float))
    if L.ndim == 1 and L.shape[0] == 5:
        L = L.reshape(1, 5)
    if L.ndim != 2 or L.shape[1] != 5:
        raise ValueError(f"velocity_gradients must have shape (S, 5) [L11, L12, L21, L22, L33] (got {L.shape})")
    if not np.all(np.isfinite(L)):
        raise ValueError("velocity_gradients must be finite")
    if not (np.isfinite(dt) and dt > 0.0):
        raise ValueError(f"dt must be > 0 (got {dt})")
    s0 = [float(v) for v in initial_stress]
    if len(s0) != 4:
        raise ValueError(f"initial_stress must have 4 components [11, 22, 33, 12] (got {len(s0)})")
    material_json = json.dumps(mat.model_dump(mode="json"))
    stresses, states, names = core().material_response(material_json, L, float(dt), s0)
    return MaterialPointResponse(np.asarray(stresses), np.asarray(states), names)


def yield_ratio(friction_angle: float) -> float:
    """k = (1 + sin φ)/(1 − sin φ): σ1/σ3 (compressions) at Mohr–Coulomb failure for c = 0."""
    s = np.sin(np.radians(friction_angle))
    return float((1.0 + s) / (1.0 - s))


@dataclass
class TriaxialResult:
    """A drained (constant confining stress) compression test, per step."""

    axial_strain: NDArray[np.float64]  # compression positive (engineering sum of rates·dt)
    volumetric_strain: NDArray[np.float64]  # compression positive
    stresses: NDArray[np.float64]  # (S, 4), tension positive
    states: NDArray[np.float64]  # (S, k), summed over steps
    state_names: list[str]
    lateral_rates: NDArray[np.float64]

    @property
    def axial_stress(self) -> NDArray[np.float64]:
        """Axial compression (positive)."""
        return -self.stresses[:, 1]

    @property
    def lateral_stress(self) -> NDArray[np.float64]:
        """Lateral (11) compression (positive)."""
        return -self.stresses[:, 0]

    def state(self, name: str) -> NDArray[np.float64]:
        return self.states[:, self.state_names.index(name)]


def drained_triaxial(
    material: dict[str, Any],
    confining: float,
    axial_strain: float = 0.05,
    steps: int = 500,
    kind: str = "triaxial",
    dt: float = 1e-3,
) -> TriaxialResult:
    """Drained compression at constant confining stress ``confining`` (Pa, compression > 0).

    ``kind="triaxial"``: axisymmetric, both lateral directions (11 and 33) at the confining
    stress — the Mohr–Coulomb return is on the triaxial-compression edge σ1 = σ2.
    ``kind="biaxial"``: plane strain (L33 = 0), σ11 held at the confining stress — σ33 is
    the intermediate principal stress and the return is on the Mohr–Coulomb plane.
    The sample starts from the isotropic state −confining.
    """
    if kind not in ("triaxial", "biaxial"):
        raise ValueError(f"kind must be 'triaxial' or 'biaxial' (got {kind!r})")
    validate_material(material)
    rate = -axial_strain / (steps * dt)  # L22 < 0: axial shortening
    stress = np.array([-confining, -confining, -confining, 0.0])

    def one(lat: float, s0: NDArray[np.float64]) -> MaterialPointResponse:
        L = [lat, 0.0, 0.0, rate, lat if kind == "triaxial" else 0.0]
        return material_point(material, [L], dt, s0)

    out_s, out_q, lats, ev = [], [], [], []
    total_state: NDArray[np.float64] | None = None
    names: list[str] = []
    lat_guess = -0.3 * rate
    for _ in range(steps):
        # secant iteration on g(lat) = σ11(lat) + confining
        x0, x1 = lat_guess, lat_guess + 1e-3 * abs(rate) + 1e-12
        r0 = one(x0, stress)
        g0 = r0.stresses[0, 0] + confining
        r1 = one(x1, stress)
        g1 = r1.stresses[0, 0] + confining
        for _it in range(20):
            if g1 == g0:
                break
            x2 = x1 - g1 * (x1 - x0) / (g1 - g0)
            x0, g0 = x1, g1
            x1 = x2
            r1 = one(x1, stress)
            g1 = r1.stresses[0, 0] + confining
            if abs(g1) <= 1e-10 * max(confining, 1.0):
                break
        stress = r1.stresses[0].copy()
        lat_guess = x1
        names = r1.state_names
        st = r1.states[0]
        total_state = st.copy() if total_state is None else total_state + st
        out_s.append(stress)
        out_q.append(total_state.copy())
        lats.append(x1)
        lateral_sum = 2.0 * x1 if kind == "triaxial" else x1
        ev.append(-(rate + lateral_sum) * dt)
    return TriaxialResult(
        axial_strain=np.arange(1, steps + 1) * (-rate * dt),
        volumetric_strain=np.cumsum(ev),
        stresses=np.array(out_s),
        states=np.array(out_q),
        state_names=list(names),
        lateral_rates=np.array(lats),
    )
