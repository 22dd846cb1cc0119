"""axmpm.cases.column_collapse.laws: empirical column-collapse laws with sources and confidence flags."""

import math

import pytest

from axmpm.cases.column_collapse.laws import LAWS, LUBE_2004, LAJEUNESSE_2004_KK, LAJEUNESSE_2004_STARON, \
    LAJEUNESSE_2005_HEIGHT, compare, get_law


def test_every_law_has_source_and_flag():
    for law in LAWS:
        assert law.source and law.via
        assert isinstance(law.confirmed, bool)
        p = law.predict(1.0)
        assert p.runout is not None or p.height is not None


@pytest.mark.parametrize("a, expected", [(0.56, 1.24 * 0.56), (0.8, 0.992), (1.0, 1.24),
                                         (5.4, 1.6 * math.sqrt(5.4)), (4.0, 3.2)])
def test_lube_runout_values(a, expected):
    p = LUBE_2004.predict(a)
    assert p.runout == pytest.approx(expected)
    assert p.runout_radius == pytest.approx(1 + expected)
    assert p.runout_confirmed is True


def test_lube_runout_nearly_continuous_at_transition():
    jumps = [d for d in LUBE_2004.discontinuities() if d["quantity"] == "runout"]
    assert len(jumps) == 1 and jumps[0]["a"] == 1.7
    assert abs(jumps[0]["relative_jump"]) < 0.015  # 2.108 -> 2.086
    below, above = LUBE_2004.predict(1.7 - 1e-9).runout, LUBE_2004.predict(1.7 + 1e-9).runout
    assert abs(above - below) / below < 0.015


def test_lube_height_regimes_and_unconfirmed_coefficient():
    assert LUBE_2004.predict(0.56).height == pytest.approx(0.56)  # H∞ = H_i
    assert LUBE_2004.predict(0.56).height_confirmed is True
    assert LUBE_2004.predict(1.2).height == pytest.approx(1.2)
    assert LUBE_2004.predict(1.2).height_confirmed is False
    p = LUBE_2004.predict(5.4)
    assert p.height == pytest.approx(0.88 * 5.4 ** (1 / 6))
    assert p.height_confirmed is False
    assert LUBE_2004.confirmed is False  # the law as a whole is not fully confirmed
    # documented discontinuity of the height law at a = 1.7
    (jump,) = [d for d in LUBE_2004.discontinuities() if d["quantity"] == "height" and d["a"] == 1.7]
    assert jump["below"] == pytest.approx(1.7) and jump["above"] == pytest.approx(0.88 * 1.7 ** (1 / 6))
    assert "1.7" in LUBE_2004.notes


def test_lajeunesse_variants_and_plateau():
    assert LAJEUNESSE_2004_KK.predict(0.56).runout == pytest.approx(1.35 * 0.56)
    assert LAJEUNESSE_2004_STARON.predict(0.56).runout == pytest.approx(0.56)
    for law in (LAJEUNESSE_2004_KK, LAJEUNESSE_2004_STARON):
        assert law.predict(5.4).runout == pytest.approx(2.0 * math.sqrt(5.4))
        assert law.predict(0.5).runout_confirmed is False
        assert law.predict(5.4).runout_confirmed is True
        assert law.predict(1.0).height is None
        assert not law.confirmed
        (jump,) = law.discontinuities()
        assert jump["a"] == 0.74 and jump["relative_jump"] > 0.5  # documented, not smoothed
    # table of docs/validation-sources.md §2
    assert LAJEUNESSE_2004_KK.predict(0.8).runout == pytest.approx(1.79, abs=0.005)
    assert LAJEUNESSE_2004_KK.predict(5.4).runout == pytest.approx(4.65, abs=0.005)
    h = LAJEUNESSE_2005_HEIGHT
    assert h.predict(0.5).height == pytest.approx(0.5)
    assert h.predict(3.0).height == pytest.approx(0.74)
    (jump,) = h.discontinuities()
    assert jump["relative_jump"] == pytest.approx(0.0, abs=1e-12)  # continuous at 0.74
    assert h.predict(3.0).runout is None


def test_compare_relative_differences():
    out = compare(0.56, 0.69440, 0.56, 0.03)
    lube = out["lube2004"]
    assert lube["runout_normalised_rel_diff"] == pytest.approx(0.0, abs=1e-4)
    assert lube["runout_radius"] == pytest.approx(0.03 * (1 + 1.24 * 0.56))
    assert lube["final_height"] == pytest.approx(0.03 * 0.56)
    assert out["lajeunesse2005_height"]["runout_radius"] is None
    assert get_law("lube2004") is LUBE_2004
    with pytest.raises(KeyError):
        get_law("nope")
    with pytest.raises(ValueError):
        LUBE_2004.predict(0.0)


def test_planar_laws_are_unconfirmed_and_tabulated_for_plane_strain():
    from axmpm.cases.column_collapse.laws import (KUMAR_2015_DEM, LAJEUNESSE_2005_PLANAR, LUBE_2005_PLANAR,
                                                  PLANAR_LAWS, laws_for, primary_law)

    # docs/physics.md §6a: secondary quotations of medium–low confidence: none confirmed (dashed).
    for law in PLANAR_LAWS:
        assert law.source and law.via and not law.confirmed
        assert all(not r.confirmed for r in law.runout)
    assert LUBE_2005_PLANAR.predict(1.0).runout == pytest.approx(1.2)
    assert LUBE_2005_PLANAR.predict(5.4).runout == pytest.approx(1.9 * 5.4 ** (2 / 3))
    assert LAJEUNESSE_2005_PLANAR.predict(2.0).runout == pytest.approx(3.6)
    assert LAJEUNESSE_2005_PLANAR.predict(10.0).runout == pytest.approx(2.3 * 10 ** (2 / 3))
    assert KUMAR_2015_DEM.predict(1.0).runout == pytest.approx(1.67)
    assert laws_for("plane_strain") is PLANAR_LAWS and laws_for("axisymmetric") is LAWS
    assert primary_law("plane_strain") is LUBE_2005_PLANAR and primary_law() is LUBE_2004
    with pytest.raises(ValueError):
        laws_for("3d")
    out = compare(5.4, 7.0, 1.0, 0.03, "plane_strain")
    assert set(out) == {"lube2005_planar", "lajeunesse2005_planar", "kumar2015_dem"}
    lube = out["lube2005_planar"]
    assert lube["runout_confirmed"] is False
    assert lube["runout_normalised_rel_diff"] == pytest.approx(7.0 / (1.9 * 5.4 ** (2 / 3)) - 1.0)
    assert get_law("kumar2015_dem") is KUMAR_2015_DEM


def test_runout_formula_states_each_regime_with_its_range_and_marks_unconfirmed_ones():
    from axmpm.cases.column_collapse.laws import LAJEUNESSE_2004_KK, LUBE_2004, LUBE_2005_PLANAR

    assert LUBE_2004.runout_formula() == "1.24 a (a < 1.7), 1.6 a^0.5 (a > 1.7)"
    # Only the unconfirmed branch of a law with a confirmed one is marked.
    assert LAJEUNESSE_2004_KK.runout_formula() == "1.35 a (a < 0.74) (unconf.), 2 a^0.5 (a > 0.74)"
    assert LUBE_2005_PLANAR.runout_formula() == "1.2 a (a < 2.3), 1.9 a^(2/3) (a > 2.3)"
