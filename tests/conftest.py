"""Shared fixtures: a tiny scenario and a helper running the CLI in a subprocess."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"

# A few hundred particles, well under a second: a block of soil settling on a fixed base.
TINY_TOML = """\
[simulation]
formulation = "plane_strain"
shape_function = "linear"
end_time = 0.1
output_interval = 0.025
gravity = [0.0, -10.0]

[grid]
extent = [0.1, 0.2]
cell_size = 0.01

[materials.soil]
model = "linear_elastic"
density = 1000.0
youngs_modulus = 1.0e5
poisson_ratio = 0.3

[[bodies]]
name = "block"
material = "soil"
min = [0.0, 0.0]
max = [0.05, 0.1]

[boundaries]
left = "roller"
bottom = "fixed"
"""


def settling_block(**simulation: object) -> dict:
    """A damped elastic block dropped onto a fixed base (plane strain, a few dozen particles):
    it comes to rest well before its end time. ``simulation`` keys override."""
    return {
        "simulation": {"formulation": "plane_strain", "shape_function": "linear", "end_time": 20.0,
                       "output_interval": 0.25, "gravity": [0.0, -10.0], "damping": 0.5,
                       "stop_at_rest_after": 0.5, **simulation},
        "grid": {"extent": [0.4, 0.4], "cell_size": 0.05},
        "materials": {"m": {"model": "linear_elastic", "density": 1000.0, "youngs_modulus": 1e5,
                            "poisson_ratio": 0.3}},
        "bodies": [{"material": "m", "min": [0.1, 0.0], "max": [0.3, 0.2]}],
        "boundaries": {"bottom": "fixed"},
    }


#: settling_block keys of a pure-FLIP run that stops once settled (work of gravity flat for 1 s).
SETTLED_STOP = {"flip_fraction": 1.0, "stop_when_settled": 1e-4, "settle_window": 1.0}


@pytest.fixture
def tiny_toml(tmp_path: Path) -> Path:
    path = tmp_path / "tiny.toml"
    path.write_text(TINY_TOML)
    return path


def run_cli(*args: str, cwd: Path | None = None, timeout: float = 120) -> subprocess.CompletedProcess[str]:
    """Run ``python -m axmpm.cli ARGS`` the way a user runs ``axmpm ARGS``."""
    env = dict(os.environ, MPLBACKEND="Agg")
    return subprocess.run(
        [sys.executable, "-m", "axmpm.cli", *map(str, args)],
        capture_output=True,
        text=True,
        cwd=cwd,
        env=env,
        timeout=timeout,
    )
