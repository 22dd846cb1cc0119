"""Animated GIF of a column collapse: the particles of every output frame, coloured
by speed, written with matplotlib's Pillow writer (Pillow is a matplotlib dependency)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from ...run.output import load_run

__all__ = ["animate_collapse", "write_animations"]


def animate_collapse(run_dir: str | Path, path: str | Path, fps: int = 8, max_frames: int = 60,
                     title: str = "") -> Path:
    """Write ``path`` (a GIF): the run's particles at each output frame (at most ``max_frames``,
    evenly picked, always with the last), axes in units of R_i, colour = |v| on one scale for
    the whole run. Returns ``path``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.animation import FuncAnimation, PillowWriter

    run = load_run(run_dir)
    frames = run.frames
    if not frames:
        raise ValueError(f"{run_dir}: no frames to animate")
    picks = np.unique(np.linspace(0, len(frames) - 1, min(max_frames, len(frames))).round().astype(int))
    body = run.scenario.bodies[0]
    radius = body.max[0] - body.min[0]
    data = [frames[i] for i in picks]
    speed_max = max(float(np.hypot(*f.v.T).max()) for f in data) or 1.0
    x_max = max(float(f.x[:, 0].max()) for f in data) / radius
    z_max = max(float(f.x[:, 1].max()) for f in data) / radius

    fig, ax = plt.subplots(figsize=(7.0, max(2.4, min(6.0, 7.0 * z_max / max(x_max, 1e-9) + 0.8))))
    first = data[0]
    size = max(0.2, min(4.0, 4000.0 / first.x.shape[0]))
    scatter = ax.scatter(first.x[:, 0] / radius, first.x[:, 1] / radius, c=np.hypot(*first.v.T), s=size,
                         cmap="viridis", vmin=0.0, vmax=speed_max, linewidths=0)
    fig.colorbar(scatter, ax=ax, label="|v| (m/s)")
    ax.set_xlim(0.0, 1.02 * x_max)
    ax.set_ylim(-0.02 * z_max, 1.05 * z_max)
    ax.set_aspect("equal")
    ax.set_xlabel("r / R_i")
    ax.set_ylabel("z / R_i")
    label = ax.set_title("")

    def draw(k: int) -> tuple:
        f = data[k]
        scatter.set_offsets(f.x / radius)
        scatter.set_array(np.hypot(*f.v.T))
        label.set_text(f"{title}  t = {f.time:.2f} s".strip())
        return scatter, label

    animation = FuncAnimation(fig, draw, frames=len(data), blit=False)
    path = Path(path)
    animation.save(path, writer=PillowWriter(fps=fps))
    plt.close(fig)
    return path


def write_animations(cases: list[dict[str, Any]], out: Path) -> str:
    """An animated GIF per case (``NAME.gif`` in ``out``: particles coloured by speed,
    :func:`animate_collapse`) and the Markdown that shows them."""
    lines = []
    for c in cases:
        if not c.get("run_dir"):
            continue
        gif = out / f"{c['name']}.gif"
        animate_collapse(out / c["run_dir"], gif, title=f"a = {c['aspect_ratio']:.3g}")
        lines.append(f"![{c['name']}]({gif.name})")
    if not lines:
        return ""
    return ("\n".join(lines) + "\n\n*Each collapse: the particles at every output, coloured by speed "
            "(axes in units of R_i).*\n")
