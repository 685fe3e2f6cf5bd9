"""Plots of trajectories: stacked position / velocity / acceleration (/ jerk) panels.

This module imports matplotlib; ``import trajkit`` does not, and loads this module
on first use of ``trajkit.plot``. Figures are built with the object-oriented API
(no pyplot state), so they can be made in threads and in scripts without a screen.
"""

from __future__ import annotations

import io
import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from trajkit._validation import positive_scalar
from trajkit.errors import InvalidInputError
from trajkit.io.atomic import atomic_write
from trajkit.limits import Limits
from trajkit.samples import Samples
from trajkit.trajectory import Trajectory

__all__ = ["profiles", "save"]

_QUANTITIES = ("position", "velocity", "acceleration", "jerk")
_FIELDS = ("q", "qd", "qdd", "qddd")
_PER_SECOND = ("", "/s", "/s²", "/s³")
_CURVE_POINTS = 1500  # enough for smooth curves on any screen


def _dense_samples(trajectory: Trajectory, unit: str) -> Samples:
    """Samples for drawing: evenly spaced plus every breakpoint, so corners are drawn."""
    times = np.union1d(
        np.linspace(trajectory.start_time, trajectory.end_time, _CURVE_POINTS),
        trajectory.breakpoints,
    )
    values = [trajectory.evaluate(times, order) for order in range(4)]
    return Samples(times, *values, unit=unit)


def profiles(
    data: Trajectory | Samples,
    limits: Limits | None = None,
    *,
    orders: Sequence[int] = (0, 1, 2),
    degrees: bool = False,
    unit: str | None = None,
    names: Sequence[str] | None = None,
    title: str | None = None,
    width: float = 8.0,
    panel_height: float = 2.2,
) -> Figure:
    """Stacked panels, one per derivative order, a line per joint, limits dashed.

    Parameters
    ----------
    data : Trajectory or Samples
        A Trajectory is drawn from its exact polynomials; Samples as given.
    limits : Limits, optional
        Bounds drawn as dashed lines in the joint's colour (black when shared).
    orders : sequence of int
        Which panels: 0 position, 1 velocity, 2 acceleration, 3 jerk.
    degrees : bool
        Show angles in degrees (the data stay in radians).
    unit : str, optional
        Position unit for the labels; default the Samples' unit, or "rad".
    names : sequence of str, optional
        Joint labels for the legend.
    title : str, optional
        Figure title.
    width, panel_height : float
        Figure size in inches.

    Returns
    -------
    matplotlib.figure.Figure
    """
    if isinstance(data, Trajectory):
        samples = _dense_samples(data, unit or "rad")
    elif isinstance(data, Samples):
        samples = data
    else:
        raise InvalidInputError(
            f"data must be a trajkit Trajectory or Samples, got {type(data).__name__}"
        )
    panels = list(orders)
    if not panels or any(o not in (0, 1, 2, 3) for o in panels) or len(set(panels)) != len(panels):
        raise InvalidInputError(f"orders must be distinct values among 0, 1, 2, 3, got {orders}")
    if limits is not None and not isinstance(limits, Limits):
        raise InvalidInputError(f"limits must be a trajkit.Limits, got {type(limits).__name__}")
    labels = list(names) if names is not None else list(samples.names)
    if len(labels) != samples.ndof:
        raise InvalidInputError(f"names gives {len(labels)} labels for {samples.ndof} joints")
    base = unit or samples.unit
    scale = 1.0
    if degrees:
        if base != "rad":
            raise InvalidInputError(f"degrees=True needs angles in rad, but the unit is {base!r}")
        scale, base = 180.0 / np.pi, "deg"
    positive_scalar("width", width)
    positive_scalar("panel_height", panel_height)

    figure = Figure(figsize=(width, panel_height * len(panels)), layout="constrained")
    axes = figure.subplots(len(panels), 1, sharex=True, squeeze=False)[:, 0]
    colors = [f"C{j % 10}" for j in range(samples.ndof)]
    for ax, order in zip(axes, panels, strict=True):
        values = getattr(samples, _FIELDS[order]) * scale
        for j in range(samples.ndof):
            ax.plot(samples.t, values[:, j], color=colors[j], label=labels[j], linewidth=1.6)
        bounds = None if limits is None else getattr(limits, _QUANTITIES[order])
        if bounds is not None:
            lower, upper = bounds.for_ndof(_QUANTITIES[order], samples.ndof)
            _draw_bounds(ax, lower * scale, upper * scale, colors)
        ax.set_ylabel(f"{_QUANTITIES[order]} [{base}{_PER_SECOND[order]}]")
        ax.grid(True, alpha=0.3)
    axes[-1].set_xlabel("time [s]")
    axes[0].legend(loc="best", fontsize="small", ncols=min(samples.ndof, 6))
    if title:
        figure.suptitle(title)
    return figure


def _draw_bounds(ax, lower: np.ndarray, upper: np.ndarray, colors: list[str]) -> None:
    shared = np.all(lower == lower[0]) and np.all(upper == upper[0])
    for side in (lower, upper):
        if shared:
            ax.axhline(side[0], color="black", linestyle="--", linewidth=1.0, alpha=0.7)
        else:
            for j, value in enumerate(side):
                ax.axhline(value, color=colors[j], linestyle="--", linewidth=1.0, alpha=0.7)


def save(figure: Figure, path: str | os.PathLike[str], *, dpi: int = 120) -> Path:
    """Save ``figure`` atomically; the format follows the suffix (.png, .svg, .pdf)."""
    target = Path(path)
    kind = target.suffix.lower().lstrip(".")
    if kind not in {"png", "svg", "pdf"}:
        raise InvalidInputError(f"plot file must end in .png, .svg or .pdf, got {target.name!r}")
    buffer = io.BytesIO()
    figure.savefig(buffer, format=kind, dpi=dpi)
    data = buffer.getvalue()
    return atomic_write(target, lambda handle: handle.write(data))
