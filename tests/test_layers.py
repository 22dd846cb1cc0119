"""The layering of the Python package holds: the import-linter contracts of pyproject.toml
(``[tool.importlinter]``: the layers, and no import cycle between the modules of any package) are
kept, and every top-level module of ``axmpm`` has its place in the layers."""

from __future__ import annotations

import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
LINT = Path(sys.executable).with_name("lint-imports")


def contracts() -> list[dict]:
    return tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["importlinter"]["contracts"]


def test_the_import_contracts_are_kept() -> None:
    result = subprocess.run([str(LINT), "--no-cache"], capture_output=True, text=True, cwd=ROOT)
    assert result.returncode == 0, result.stdout + result.stderr
    assert f"Contracts: {len(contracts())} kept, 0 broken." in result.stdout


def test_every_top_level_module_is_in_a_layer() -> None:
    (layers,) = [c["layers"] for c in contracts() if c["type"] == "layers"]
    placed = {name.strip(" ()") for layer in layers for name in layer.replace(":", "|").split("|")}
    package = ROOT / "python" / "axmpm"
    modules = {f"axmpm.{p.stem}" for p in package.glob("*.py") if p.stem != "__init__"}
    modules |= {f"axmpm.{p.name}" for p in package.iterdir() if (p / "__init__.py").exists()}
    assert modules - placed == set(), "add these modules to a layer of [tool.importlinter] in pyproject.toml"
    assert placed - modules == set(), "these layers name no module"


def test_a_cycle_between_two_modules_is_reported(tmp_path: Path) -> None:
    """The acyclic contract does fail: a two-module package that imports itself in a circle."""
    pkg = tmp_path / "circle"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text("def f():\n    from . import b\n")
    (pkg / "b.py").write_text("from . import a\n")
    (tmp_path / ".importlinter").write_text(
        "[importlinter]\nroot_package = circle\n\n[importlinter:contract:1]\nname = no cycles\n"
        "type = acyclic_siblings\nancestors = circle\n")
    result = subprocess.run([str(LINT), "--no-cache"], capture_output=True, text=True, cwd=tmp_path,
                            env={"PYTHONPATH": str(tmp_path), "PATH": ""})
    assert result.returncode == 1, result.stdout + result.stderr
    assert "No cycles are allowed in circle." in result.stdout
