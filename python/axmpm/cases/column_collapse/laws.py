"""Empirical laws of axisymmetric granular column collapse, with their sources.

Notation: a = H_i/R_i (initial aspect ratio), R∞ final runout radius, H∞ final central
height. Every law predicts the *normalised runout* (R∞ − R_i)/R_i and/or the *normalised
final height* H∞/R_i as power laws a ↦ c·a^n over regimes of a.

Where each coefficient comes from and how far it can be trusted is recorded in
``docs/validation-sources.md`` (the primary papers could not be read; every value comes
from secondary sources). Each regime carries its own ``confidence`` ("high", "medium",
"low", "unconfirmed") and ``confirmed`` (high or medium); a law is ``confirmed`` only when
all its regimes are. Laws are not continuous at every transition: the jumps are
computed by :meth:`Law.discontinuities` and reported, not smoothed away.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

__all__ = ["Regime", "Law", "Prediction", "LAWS", "LUBE_2004", "LAJEUNESSE_2004_KK",
           "LAJEUNESSE_2004_STARON", "LAJEUNESSE_2005_HEIGHT", "PLANAR_LAWS", "LUBE_2005_PLANAR",
           "LAJEUNESSE_2005_PLANAR", "KUMAR_2015_DEM", "TABLE_LAWS", "laws_for", "get_law", "primary_law"]

CONFIRMED_LEVELS = ("high", "medium")


@dataclass(frozen=True)
class Regime:
    """value = coefficient · a^exponent for a_min < a ≤ a_max."""

    coefficient: float
    exponent: float
    a_min: float = 0.0
    a_max: float = math.inf
    confidence: str = "unconfirmed"
    source: str = ""

    @property
    def confirmed(self) -> bool:
        return self.confidence in CONFIRMED_LEVELS

    def contains(self, a: float) -> bool:
        return self.a_min < a <= self.a_max

    def __call__(self, a: float) -> float:
        return self.coefficient * a**self.exponent

    def formula(self) -> str:
        if self.exponent == 1.0:
            body = f"{self.coefficient:g} a"
        elif self.exponent == 0.0:
            body = f"{self.coefficient:g}"
        else:
            frac = {0.5: "1/2", 1 / 6: "1/6", 2 / 3: "2/3"}.get(self.exponent, f"{self.exponent:g}")
            body = f"{self.coefficient:g} a^{frac}"
        lo = "" if self.a_min == 0.0 else f"{self.a_min:g} < "
        hi = "" if math.isinf(self.a_max) else f" ≤ {self.a_max:g}"
        rng = f"{lo}a{hi}" if (lo or hi) else "all a"
        return f"{body} ({rng})"


@dataclass(frozen=True)
class Prediction:
    """Normalised predictions; None where the law says nothing."""

    runout: float | None  # (R∞ − R_i)/R_i
    height: float | None  # H∞/R_i
    runout_confirmed: bool | None
    height_confirmed: bool | None

    @property
    def runout_radius(self) -> float | None:
        """R∞/R_i."""
        return None if self.runout is None else 1.0 + self.runout


def _pick(regimes: tuple[Regime, ...], a: float) -> Regime | None:
    for r in regimes:
        if r.contains(a):
            return r
    return None


@dataclass(frozen=True)
class Law:
    """An empirical law: regimes for the normalised runout and/or the normalised height."""

    key: str
    label: str
    source: str  # citation of the paper the law is attributed to
    via: str  # the secondary sources it was read from (docs/validation-sources.md tags)
    runout: tuple[Regime, ...] = ()
    height: tuple[Regime, ...] = ()
    notes: str = ""
    extra: dict[str, Any] = field(default_factory=dict)

    @property
    def confirmed(self) -> bool:
        """True only when every regime of the law is confirmed (high or medium confidence)."""
        return all(r.confirmed for r in self.runout + self.height)

    def predict(self, a: float) -> Prediction:
        """(R∞ − R_i)/R_i and H∞/R_i at aspect ratio a (None outside the law's content)."""
        if not a > 0.0:
            raise ValueError(f"aspect ratio must be > 0 (got {a})")
        ro = _pick(self.runout, a)
        he = _pick(self.height, a)
        return Prediction(
            runout=None if ro is None else ro(a),
            height=None if he is None else he(a),
            runout_confirmed=None if ro is None else ro.confirmed,
            height_confirmed=None if he is None else he.confirmed,
        )

    def runout_formula(self) -> str:
        """The runout regimes as text, e.g. ``1.24 a (a < 1.7), 1.6 a^0.5 (a > 1.7)``; in a law
        with some confirmed regimes the unconfirmed ones are marked ``(unconf.)``."""
        mixed = any(r.confirmed for r in self.runout) and not all(r.confirmed for r in self.runout)
        parts = []
        for r in self.runout:
            if abs(r.exponent - 1.0) < 1e-12:
                power = "a"
            elif abs(r.exponent - 2 / 3) < 1e-12:
                power = "a^(2/3)"
            else:
                power = f"a^{r.exponent:g}"
            bounds = []
            if r.a_min > 0.0:
                bounds.append(f"a > {r.a_min:g}")
            if math.isfinite(r.a_max):
                bounds.append(f"a < {r.a_max:g}")
            mark = " (unconf.)" if mixed and not r.confirmed else ""
            parts.append(f"{r.coefficient:g} {power}" + (f" ({', '.join(bounds)})" if bounds else "") + mark)
        return ", ".join(parts)

    def discontinuities(self) -> list[dict[str, float | str]]:
        """Jumps at the regime transitions: quantity, a, value below, value above, relative jump."""
        out: list[dict[str, float | str]] = []
        for name, regimes in (("runout", self.runout), ("height", self.height)):
            for lo, hi in zip(regimes, regimes[1:]):
                a = lo.a_max
                below, above = lo(a), hi(a)
                out.append({"quantity": name, "a": a, "below": below, "above": above,
                            "relative_jump": (above - below) / below})
        return out

    def describe(self) -> dict[str, Any]:
        return {
            "key": self.key, "label": self.label, "source": self.source, "via": self.via,
            "confirmed": self.confirmed,
            "runout": [{"formula": r.formula(), "confidence": r.confidence} for r in self.runout],
            "height": [{"formula": r.formula(), "confidence": r.confidence} for r in self.height],
            "notes": self.notes,
        }


LUBE = "Lube, Huppert, Sparks & Hallworth (2004), J. Fluid Mech. 508:175–199"
LAJ04 = "Lajeunesse, Mangeney-Castelnau & Vilotte (2004), Phys. Fluids 16:2371"
LAJ05 = "Lajeunesse, Monnier & Homsy (2005), Phys. Fluids 17:103302"

#: Lube et al. 2004. Runout: high confidence (KK ch. 2 and two REPO quotations agree).
#: Height: H∞ = H_i while the summit is undisturbed — a ≲ 0.74 agrees with Lajeunesse's
#: H∞/R_i ≈ a (KK), so "high"; 0.74 < a ≤ 1.7 rests on AG18 alone and conflicts with the
#: Lajeunesse plateau (validation-sources "still unconfirmed" 4) → unconfirmed;
#: H∞/R_i ≈ 0.88 a^{1/6} for a > 1.7 was found in no source → unconfirmed.
LUBE_2004 = Law(
    key="lube2004",
    label="Lube et al. 2004",
    source=LUBE,
    via="KK ch. 2, REPO (runout); AG18, NI, ICTAM (height regimes); 0.88 a^1/6 not found",
    runout=(
        Regime(1.24, 1.0, 0.0, 1.7, "high", "KK ch. 2; REPO"),
        Regime(1.6, 0.5, 1.7, math.inf, "high", "KK ch. 2; REPO"),
    ),
    height=(
        Regime(1.0, 1.0, 0.0, 0.74, "high", "AG18 (Lube regimes); KK (Lajeunesse H∞/R_i ≈ a)"),
        Regime(1.0, 1.0, 0.74, 1.7, "unconfirmed", "AG18 only; conflicts with the KK plateau"),
        Regime(0.88, 1 / 6, 1.7, math.inf, "unconfirmed", "not found in any source read"),
    ),
    notes="Runout jumps by -1 % at a = 1.7 (2.108 → 2.086). The height law jumps from "
    "1.7 to 0.96 at a = 1.7: the undisturbed-summit statement and the 0.88 a^1/6 law cannot "
    "both be right there.",
)

#: Lajeunesse et al. 2004, as transcribed by KK ch. 2 (small-a coefficient 1.35).
LAJEUNESSE_2004_KK = Law(
    key="lajeunesse2004_kk",
    label="Lajeunesse et al. 2004 (KK: 1.35 a)",
    source=LAJ04,
    via="KK ch. 2 (small a); KK ch. 2 and REPO (large a)",
    runout=(
        Regime(1.35, 1.0, 0.0, 0.74, "unconfirmed", "KK ch. 2; conflicts with REPO (1.0 a)"),
        Regime(2.0, 0.5, 0.74, math.inf, "medium", "KK ch. 2; REPO"),
    ),
    notes="Discontinuous at a = 0.74 (1.00 → 1.72): at least one transcription is wrong.",
)

#: Lajeunesse et al. 2004, as quoted by REPO from Staron & Hinch (small-a coefficient 1.0).
LAJEUNESSE_2004_STARON = Law(
    key="lajeunesse2004_staron",
    label="Lajeunesse et al. 2004 (Staron & Hinch: 1.0 a)",
    source=LAJ04,
    via="REPO quoting Staron & Hinch, arXiv physics/0501022 §III (not read); large a: KK, REPO",
    runout=(
        Regime(1.0, 1.0, 0.0, 0.74, "unconfirmed", "REPO; conflicts with KK (1.35 a)"),
        Regime(2.0, 0.5, 0.74, math.inf, "medium", "KK ch. 2; REPO"),
    ),
    notes="Discontinuous at a = 0.74 (0.74 → 1.72).",
)

#: Axisymmetric height plateau, attributed by KK to Lajeunesse et al. 2005. The plateau is
#: confirmed qualitatively (MC05; doi:10.1007/s10035-016-0643-z); its value 0.74 is "low".
LAJEUNESSE_2005_HEIGHT = Law(
    key="lajeunesse2005_height",
    label="Lajeunesse et al. 2005 (height plateau)",
    source=LAJ05,
    via="KK ch. 2; plateau qualitatively: MC05, Granular Matter doi:10.1007/s10035-016-0643-z",
    height=(
        Regime(1.0, 1.0, 0.0, 0.74, "medium", "KK ch. 2"),
        Regime(0.74, 0.0, 0.74, math.inf, "low", "KK ch. 2 (value); plateau: MC05"),
    ),
    notes="Continuous at a = 0.74. The plateau value 0.74 is low-confidence.",
)

#: All laws, the primary one (runout confirmed) first.
LAWS: tuple[Law, ...] = (LUBE_2004, LAJEUNESSE_2004_KK, LAJEUNESSE_2004_STARON, LAJEUNESSE_2005_HEIGHT)

# ----------------------------------------------------------------------------- planar (channel)
# Plane-strain runs compare with two-dimensional collapses: a column of length L_i against
# the back wall of a channel, released by a gate (the roller at x = 0 of the plane-strain
# scenario is that wall), (R∞ − L_i)/L_i against a = H_i/L_i. Every value below is a
# secondary quotation (docs/physics.md §6a: "medium–low confidence"); none is
# confirmed, so every branch is drawn dashed.
PLANAR_CONFIDENCE = "medium-low"
LUBE05 = "Lube, Huppert, Sparks & Freundt (2005), J. Fluid Mech. 541 (collapses in a channel)"
KUMAR15 = "Kumar (2015), PhD thesis, University of Cambridge (2D DEM of plane-strain collapses)"

#: Lube et al. 2005: 1.2 a below the transition, 1.9 a^(2/3) above. The transition is quoted
#: as 1.8, 2.3 and 2.8 by different sources; 2.3 is used. The branches only meet at a ≈ 4.0,
#: so the law jumps there (2.76 → 3.31 at a = 2.3).
LUBE_2005_PLANAR = Law(
    key="lube2005_planar",
    label="Lube et al. 2005 (planar)",
    source=LUBE05,
    via="docs/physics.md §6a (secondary quotations)",
    runout=(
        Regime(1.2, 1.0, 0.0, 2.3, PLANAR_CONFIDENCE, "docs/physics.md §6a; transition quoted as 1.8, 2.3, 2.8"),
        Regime(1.9, 2 / 3, 2.3, math.inf, PLANAR_CONFIDENCE, "docs/physics.md §6a"),
    ),
    notes="Transition quoted as 1.8, 2.3 and 2.8; 2.3 used. The branches do not meet there "
    "(2.76 → 3.31 at a = 2.3).",
)

#: Lajeunesse, Monnier & Homsy 2005: 1.8 a (a < 3) and 2.3 a^(2/3) (a > 3), one secondary source.
LAJEUNESSE_2005_PLANAR = Law(
    key="lajeunesse2005_planar",
    label="Lajeunesse et al. 2005 (planar)",
    source=LAJ05,
    via="docs/physics.md §6a (one secondary source)",
    runout=(
        Regime(1.8, 1.0, 0.0, 3.0, PLANAR_CONFIDENCE, "docs/physics.md §6a (one source)"),
        Regime(2.3, 2 / 3, 3.0, math.inf, PLANAR_CONFIDENCE, "docs/physics.md §6a (one source)"),
    ),
    notes="Jumps at a = 3 (5.40 → 4.78).",
)

#: Kumar's 2D DEM fit: 1.67 a below a ≈ 2.3–2.7 (2.5 used) and 2.5–2.7 a^(2/3) above (2.6,
#: the middle of the quotations, used).
KUMAR_2015_DEM = Law(
    key="kumar2015_dem",
    label="Kumar 2015 (2D DEM)",
    source=KUMAR15,
    via="docs/physics.md §6a (quotations differ)",
    runout=(
        Regime(1.67, 1.0, 0.0, 2.5, PLANAR_CONFIDENCE, "docs/physics.md §6a; transition quoted 2.3–2.7"),
        Regime(2.6, 2 / 3, 2.5, math.inf, PLANAR_CONFIDENCE, "docs/physics.md §6a; coefficient quoted 2.5–2.7"),
    ),
    notes="Coefficient of the a^(2/3) branch quoted as 2.5–2.7 (2.6 used), transition 2.3–2.7 (2.5 used).",
)

#: The planar laws, the primary one first.
PLANAR_LAWS: tuple[Law, ...] = (LUBE_2005_PLANAR, LAJEUNESSE_2005_PLANAR, KUMAR_2015_DEM)

#: The runout laws tabulated per formulation (primary first).
TABLE_LAWS: dict[str, tuple[Law, ...]] = {
    "axisymmetric": (LUBE_2004, LAJEUNESSE_2004_KK),
    "plane_strain": PLANAR_LAWS,
}


def laws_for(formulation: str = "axisymmetric") -> tuple[Law, ...]:
    """The laws a run of ``formulation`` is compared with: the axisymmetric (cylinder) laws, or
    the planar (channel) laws for plane strain."""
    if formulation == "plane_strain":
        return PLANAR_LAWS
    if formulation == "axisymmetric":
        return LAWS
    raise ValueError(f"formulation must be 'axisymmetric' or 'plane_strain' (got {formulation!r})")


def get_law(key: str) -> Law:
    for law in LAWS + PLANAR_LAWS:
        if law.key == key:
            return law
    raise KeyError(f"unknown law {key!r}; known: {', '.join(l.key for l in LAWS + PLANAR_LAWS)}")


def primary_law(formulation: str = "axisymmetric") -> Law:
    """The law the targets refer to: Lube et al. 2004 (axisymmetric), Lube et al. 2005
    (plane strain; unconfirmed)."""
    return laws_for(formulation)[0]


def compare(a: float, runout_normalised: float, height_normalised: float,
            radius: float, formulation: str = "axisymmetric") -> dict[str, dict[str, Any]]:
    """Each law of the formulation (:func:`laws_for`): its predicted R∞ and H∞ (metres, for
    initial radius or length ``radius``) and the simulation's relative difference
    (sim − law)/law; None where a law is silent."""
    out: dict[str, dict[str, Any]] = {}
    R_sim = radius * (1.0 + runout_normalised)
    H_sim = radius * height_normalised
    for law in laws_for(formulation):
        p = law.predict(a)
        entry: dict[str, Any] = {"label": law.label, "source": law.source, "confirmed": law.confirmed}
        if p.runout is not None:
            R_law = radius * (1.0 + p.runout)
            entry.update(
                runout_radius=R_law,
                runout_normalised=p.runout,
                runout_confirmed=p.runout_confirmed,
                runout_radius_rel_diff=(R_sim - R_law) / R_law,
                runout_normalised_rel_diff=(runout_normalised - p.runout) / p.runout,
            )
        else:
            entry.update(runout_radius=None, runout_normalised=None, runout_confirmed=None,
                         runout_radius_rel_diff=None, runout_normalised_rel_diff=None)
        if p.height is not None:
            H_law = radius * p.height
            entry.update(final_height=H_law, final_height_normalised=p.height,
                         height_confirmed=p.height_confirmed,
                         final_height_rel_diff=(H_sim - H_law) / H_law)
        else:
            entry.update(final_height=None, final_height_normalised=None, height_confirmed=None,
                         final_height_rel_diff=None)
        out[law.key] = entry
    return out
