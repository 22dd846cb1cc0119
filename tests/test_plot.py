"""``axmpm plot``: history.csv columns drawn as they are in the file, and clear input errors."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest

import axmpm
from axmpm.run.plot import history_figure, plot_history
from conftest import TINY_TOML, run_cli


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("plot")
    (folder / "tiny.toml").write_text(TINY_TOML)
    out = folder / "run"
    summary = axmpm.run(axmpm.Scenario.from_toml(folder / "tiny.toml"), out, threads=1, progress=False)
    assert summary["status"] == "completed"
    return out


def csv_columns(path: Path) -> dict[str, np.ndarray]:
    """history.csv read with the csv module alone (not through axmpm)."""
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    return {name: np.array([float(r[j]) for r in rows[1:]]) for j, name in enumerate(rows[0])}


def lines_by_label(fig) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    return {line.get_label(): (np.asarray(line.get_xdata()), np.asarray(line.get_ydata()))
            for line in fig.axes[0].get_lines()}


def test_the_plotted_lines_are_the_csv_columns(run_dir: Path) -> None:
    data = csv_columns(run_dir / "history.csv")
    assert len(data["time"]) >= 4
    fig = history_figure(axmpm.load_run(run_dir).history, ["bottom.force_y", "kinetic_energy"])
    lines = lines_by_label(fig)
    assert sorted(lines) == ["bottom.force_y (N)", "kinetic_energy (J)"]
    for label, (x, y) in lines.items():
        np.testing.assert_array_equal(x, data["time"])
        np.testing.assert_array_equal(y, data[label.split()[0]])
    assert fig.axes[0].get_xlabel() == "time (s)"


def test_against_another_column_negated(run_dir: Path) -> None:
    data = csv_columns(run_dir / "history.csv")
    fig = history_figure(axmpm.load_run(run_dir).history, ["bottom.force_y"], x="gravity_work",
                         negate_x=True, negate_y=True)
    (x, y), = lines_by_label(fig).values()
    np.testing.assert_array_equal(x, -data["gravity_work"])
    np.testing.assert_array_equal(y, -data["bottom.force_y"])
    assert np.any(data["bottom.force_y"] != 0.0)  # the sign flip is seen
    assert fig.axes[0].get_xlabel() == "−gravity_work (J)"
    assert fig.axes[0].get_ylabel() == "−bottom.force_y (N)"
    per_metre = history_figure(axmpm.load_run(run_dir).history, ["bottom.force_y"], per_metre=True)
    assert per_metre.axes[0].get_ylabel() == "bottom.force_y (N/m)"


def test_default_columns_are_the_energies(run_dir: Path) -> None:
    from axmpm.run.plot import energy_columns

    names = energy_columns(list(csv_columns(run_dir / "history.csv")))
    assert {"kinetic_energy", "elastic_energy", "gravity_work"} <= set(names)
    assert not {"time", "steps", "dt", "wall_seconds", "bottom.force_y"} & set(names)


def test_the_command_writes_a_png(run_dir: Path, tmp_path: Path) -> None:
    out = tmp_path / "figs" / "load.png"
    result = run_cli("plot", run_dir, "bottom.force_y", "--x", "time", "--out", out)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == f"wrote {out}"
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    default = plot_history(run_dir)
    assert default == run_dir / "plot.png" and default.stat().st_size > 1000


@pytest.mark.parametrize("args", [("left.force_z",), ("bottom.force_y", "--x", "settlement")])
def test_an_unknown_column_is_named_with_the_columns_there_are(run_dir: Path, args: tuple[str, ...]) -> None:
    result = run_cli("plot", run_dir, *args)
    assert result.returncode == 2
    assert "Traceback" not in result.stderr
    unknown = args[-1]
    assert f"no column '{unknown}'" in result.stderr
    assert "its columns are: time, steps, dt," in result.stderr and "bottom.force_y" in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1


def test_not_a_run_folder(tmp_path: Path) -> None:
    result = run_cli("plot", tmp_path)
    assert result.returncode == 2 and "not an axmpm run folder" in result.stderr
