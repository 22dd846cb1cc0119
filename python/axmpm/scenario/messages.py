"""Pydantic validation errors → ``(dotted key, message)`` pairs with the wording of
docs/robustness.md (ranges, "did you mean", the models a key belongs to)."""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel, ValidationError

from .boundaries import Boundaries, BoundaryCondition, Wall
from .fields import did_you_mean
from .materials import MATERIAL_MODELS, MaterialModel, engine_key_errors, model_names
from .regions import REGION_SHAPES, shape_names
from .rigid_bodies import RIGID_BODY_SHAPES
from .sections import Grid, Simulation

__all__ = ["convert_errors", "dotted"]

#: The sections whose tables are discriminated by their region's ``shape``: shape → class.
_SHAPED: dict[str, dict[str, type[Any]]] = {"bodies": REGION_SHAPES, "rigid_bodies": RIGID_BODY_SHAPES}

_SECTION_MODELS: dict[str, type[BaseModel]] = {
    "simulation": Simulation,
    "grid": Grid,
    "boundaries": Boundaries,
    "walls": Wall,
}


def _tagged(loc: tuple[Any, ...]) -> bool:
    """``loc`` = (section, name or index, tag, ...) with the discriminator tag of a union."""
    if len(loc) < 3:
        return False
    if loc[0] == "materials":
        return str(loc[2]) in MATERIAL_MODELS
    shapes = _SHAPED.get(str(loc[0]))
    return shapes is not None and len(shapes) > 1 and str(loc[2]) in shapes


def _model_at(loc: tuple[Any, ...], root: type[BaseModel] | None) -> type[BaseModel] | None:
    """The model class validating the table at ``loc`` (pydantic location, tags included);
    ``root`` validates the whole document (location ``()``)."""
    if not loc:
        return root
    section = loc[0]
    if section == "materials":
        return MATERIAL_MODELS.get(str(loc[2])) if len(loc) == 3 else None
    if section in _SHAPED:
        shapes = _SHAPED[section]
        if len(loc) == 3 and _tagged(loc):
            return shapes[str(loc[2])]
        if len(loc) == 2 and len(shapes) == 1:
            return next(iter(shapes.values()))
        return None
    if section == "walls":
        return Wall if len(loc) == 2 else None
    if section == "boundaries":
        return Boundaries if len(loc) == 1 else BoundaryCondition
    if len(loc) == 1:
        return _SECTION_MODELS.get(str(section))
    return None


def dotted(loc: tuple[Any, ...]) -> str:
    """Pydantic location → dotted key, dropping the discriminator tag of materials and bodies."""
    parts = list(loc)
    if _tagged(loc):
        del parts[2]
    return ".".join(str(p) for p in parts)


def _retired_message(loc: tuple[Any, ...], value: Any) -> str | None:
    """The engine's message for an unknown key that a material model no longer has (``loc`` =
    materials, NAME, MODEL, KEY in a scenario; MODEL, KEY for one material table), else None."""
    if len(loc) == 4 and loc[0] == "materials":
        name, model = str(loc[1]), str(loc[2])
    elif len(loc) == 2 and str(loc[0]) in MATERIAL_MODELS:
        name, model = "material", str(loc[0])
    else:
        return None
    found = engine_key_errors(name, {"model": model, str(loc[-1]): value})
    return found[0][1] if found else None


def convert_errors(exc: ValidationError, root: type[BaseModel] | None = None) -> list[tuple[str, str]]:
    """One ``(dotted key, message)`` per error of ``exc``; ``root`` is the model of the whole
    document (the scenario), whose fields an unknown top-level key is compared with."""
    out: list[tuple[str, str]] = []
    for err in exc.errors(include_url=False):
        loc = tuple(err["loc"])
        kind = err["type"]
        ctx = err.get("ctx") or {}
        value = err.get("input")
        msg = err["msg"]
        if kind == "extra_forbidden":
            model = _model_at(loc[:-1], root)
            fields = list(model.model_fields) if model else []
            msg = "unknown key" + did_you_mean(loc[-1], fields)
            retired = _retired_message(loc, value)
            if retired is not None:
                msg = retired
            elif model is not None and issubclass(model, MaterialModel):
                owners = [n for n in model_names() if loc[-1] in MATERIAL_MODELS[n].model_fields]
                if owners and "did you mean" not in msg:
                    msg += f" (only valid for model = {' or '.join(repr(o) for o in owners)})"
            elif model is not None and loc and loc[0] in _SHAPED:
                owners = [n for n in shape_names() if loc[-1] in _SHAPED[loc[0]][n].model_fields]
                if owners and "did you mean" not in msg:
                    msg += f" (only valid for shape = {' or '.join(repr(o) for o in owners)})"
        elif kind == "missing" and loc and isinstance(loc[-1], int):
            loc = loc[:-1]  # a too-short tuple reports its first missing index
            msg = f"must have exactly 2 entries (got {len(value) if isinstance(value, (list, tuple)) else value!r})"
        elif kind == "missing":
            msg = "required key is missing"
        elif kind == "literal_error":
            msg = f"must be {ctx.get('expected', '')} (got {value!r})"
            if isinstance(value, str):
                choices = [c.strip(" '") for c in str(ctx.get("expected", "")).replace(" or ", ",").split(",")]
                msg += did_you_mean(value, choices)
        elif kind == "union_tag_invalid" and loc and loc[0] in _SHAPED:
            loc = loc + ("shape",)
            msg = f"unknown shape {ctx.get('tag')!r}; expected one of {', '.join(repr(n) for n in shape_names())}"
            msg += did_you_mean(ctx.get("tag", ""), REGION_SHAPES)
        elif kind == "union_tag_invalid":
            loc = loc + ("model",)
            expected = ", ".join(repr(n) for n in model_names())
            msg = f"unknown material model {ctx.get('tag')!r}; expected one of {expected}"
            msg += did_you_mean(ctx.get("tag", ""), MATERIAL_MODELS)
        elif kind == "union_tag_not_found":
            loc = loc + ("model",)
            msg = "required key is missing (one of " + ", ".join(repr(m) for m in model_names()) + ")"
        elif kind in ("too_long", "too_short") and isinstance(value, (list, tuple)):
            msg = f"must have exactly 2 entries (got {len(value)})" if "tuple" in msg.lower() else msg
        elif kind in ("float_parsing", "float_type", "int_parsing", "int_type", "int_from_float"):
            msg = f"{msg.rstrip('.')} (got {value!r})"
        elif kind in ("finite_number",):
            msg = f"must be a finite number (got {value!r})"
        out.append((dotted(loc), msg))
    return out
