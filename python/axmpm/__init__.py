"""axmpm: material point method for large-deformation geomechanics (plane strain and
axisymmetric). Rust engine (``axmpm._core``), Python front end (this package)."""

from .errors import RunError, ScenarioError
from .scenario import Scenario, apply_overrides

__all__ = ["Scenario", "ScenarioError", "RunError", "apply_overrides", "run", "load_run", "material_point"]


def __getattr__(name: str):
    # Lazy: importing axmpm must not need the compiled engine or matplotlib.
    if name == "__version__":  # the installed distribution's, from pyproject.toml
        from importlib.metadata import PackageNotFoundError, version

        try:
            return version("axmpm")
        except PackageNotFoundError:  # imported from a source tree that was never installed
            return "unknown"
    if name == "run":  # the package axmpm.run, callable as axmpm.run(scenario, out, ...)
        import importlib

        return importlib.import_module(".run", __name__)
    if name == "load_run":
        from .run.output import load_run

        return load_run
    if name == "material_point":
        from .material_driver import material_point

        return material_point
    raise AttributeError(f"module 'axmpm' has no attribute {name!r}")
