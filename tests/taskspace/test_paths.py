"""Tests of trajkit.taskspace.paths: Line, Arc, Ellipse, FigureEight, Polyline.

Derivatives are checked against central differences, the bounds against dense grids,
and each family against its defining formula (seed 002's segment and figure eight).
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import support
from support import FINITE_DIFFERENCE
from trajkit.errors import InvalidInputError
from trajkit.rotations import axis_rotation
from trajkit.taskspace import Arc, Ellipse, FigureEight, Line, Path, Polyline

# Tolerances ---------------------------------------------------------------------
GEOMETRY = 1e-12  # absolute, on O(1) coordinates: closed-form points of the paths
FD_STEP = 1e-5  # step in u of the central differences
BOUND_SLACK = 1e-12  # relative: a bound may be attained, up to rounding
GRID = 4001  # points of the dense grid in u
FEW = settings(max_examples=40, deadline=None)


def paths() -> dict[str, Path]:
    """One of each family, in general position (tilted planes, offsets, odd sweeps)."""
    return {
        "line": Line([0.0, -12.0, 20.0], [10.0, 12.0, 20.0]),
        "line2d": Line([0.5, -1.0], [-2.0, 3.0]),
        "arc": Arc([1.0, 0.0, 0.0], [2.0, 0.0, 0.5], 1.5 * np.pi, normal=[0.0, 1.0, 1.0]),
        "arc_negative": Arc([0.0, 0.0, 0.0], [0.0, 0.7, 0.0], -2.5 * np.pi),
        "ellipse": Ellipse([0.0, 1.0, 0.0], 0.8, 0.3, turns=1.5, phase=0.4),
        "ellipse_tilted": Ellipse(
            [0.2, -0.1, 0.3], 0.6, 0.4, turns=-0.75, normal=[1.0, 1.0, 1.0], x_axis=None
        ),
        "segment": Ellipse([0.0, 1.2, 0.0], 0.9, 0.0),
        "eight": FigureEight([0.5, 0.0, 0.0], 2.0, 1.0),
        "eight_vertical": FigureEight(
            [0.0, 0.3, 1.0], 0.8, 1.4, normal=[0.0, 1.0, 0.0], x_axis=[1.0, 0.0, 0.3]
        ),
        "polyline": Polyline([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 2.0, 0.0], [0.0, 2.0, 1.0]]),
        "polyline2d": Polyline([[0.0, 0.0], [3.0, 4.0], [3.0, 0.0]]),
    }


NAMES = list(paths())
SMOOTH = [n for n in NAMES if not n.startswith("polyline")]


def central_difference(path: Path, u: np.ndarray, order: int) -> np.ndarray:
    """d/du of the (order - 1)-th derivative by a central difference."""
    plus = path.evaluate(u + FD_STEP, order - 1)
    minus = path.evaluate(u - FD_STEP, order - 1)
    return (plus - minus) / (2 * FD_STEP)


def assert_bounds_hold(path: Path) -> None:
    u = np.linspace(0.0, 1.0, GRID)
    speed = np.linalg.norm(path.evaluate(u, 1), axis=1)
    curvature = np.linalg.norm(path.evaluate(u, 2), axis=1)
    assert speed.max() <= path.speed_bound * (1 + BOUND_SLACK)
    assert curvature.max() <= path.curvature_bound * (1 + BOUND_SLACK) + BOUND_SLACK


def signed_sweep(points: np.ndarray, center: np.ndarray, normal: np.ndarray) -> float:
    """Total signed angle (rad) swept about ``normal`` by densely sampled points."""
    radial = points - center
    e1 = radial[0] / np.linalg.norm(radial[0])
    e2 = np.cross(normal, e1)
    angles = np.unwrap(np.arctan2(radial @ e2, radial @ e1))
    return float(angles[-1] - angles[0])


# ----------------------------------------------------------------------- derivatives
@pytest.mark.parametrize("name", SMOOTH)
@pytest.mark.parametrize("order", [1, 2])
def test_derivatives_match_central_differences(name, order):
    path = paths()[name]
    u = np.linspace(0.0, 1.0, 101)  # the formulas hold beyond [0, 1] too: ends included
    support.assert_state(
        path.evaluate(u, order), central_difference(path, u, order), rtol=FINITE_DIFFERENCE
    )


@pytest.mark.parametrize("name", ["polyline", "polyline2d"])
@pytest.mark.parametrize("order", [1, 2])
def test_polyline_derivatives_match_central_differences_inside_segments(name, order):
    path = paths()[name]
    knots = path.knots
    # Points well inside each segment, so that u +- FD_STEP stays on one segment.
    u = np.concatenate([np.linspace(a, b, 12)[1:-1] for a, b in itertools.pairwise(knots)])
    support.assert_state(
        path.evaluate(u, order), central_difference(path, u, order), rtol=FINITE_DIFFERENCE
    )


@pytest.mark.parametrize("name", NAMES)
def test_evaluate_shapes_and_scalar_input(name):
    path = paths()[name]
    for order in (0, 1, 2):
        assert path.evaluate(0.3, order).shape == (1, 3)
        assert path.evaluate(np.linspace(0, 1, 7), order).shape == (7, 3)
    np.testing.assert_array_equal(path.start, path.evaluate(0.0)[0])
    np.testing.assert_array_equal(path.end, path.evaluate(1.0)[0])


# ----------------------------------------------------------------------------- bounds
@pytest.mark.parametrize("name", NAMES)
def test_bounds_hold_on_a_dense_grid(name):
    assert_bounds_hold(paths()[name])


def test_line_bounds_are_exact_and_arc_speed_is_constant():
    line = Line([1.0, 2.0, 3.0], [4.0, 6.0, 3.0])
    assert line.speed_bound == pytest.approx(5.0, rel=support.ROUNDING)
    assert line.curvature_bound == 0.0
    radius, angle = 2.0, 0.75 * np.pi
    arc = Arc([0.0, 0.0, 0.0], [radius, 0.0, 0.0], angle)
    u = np.linspace(0, 1, 11)
    # |p'| = r |angle| and |p''| = r angle^2 at every point of an arc; the bounds cover
    # them (the conic family's bounds are conservative: sqrt(2) times these for a circle).
    speed = np.linalg.norm(arc.evaluate(u, 1), axis=1)
    curvature = np.linalg.norm(arc.evaluate(u, 2), axis=1)
    np.testing.assert_allclose(speed, radius * angle, rtol=support.ROUNDING)
    np.testing.assert_allclose(curvature, radius * angle**2, rtol=support.ROUNDING)
    assert radius * angle <= arc.speed_bound <= np.sqrt(2) * radius * angle * (1 + BOUND_SLACK)
    assert (
        radius * angle**2
        <= arc.curvature_bound
        <= np.sqrt(2) * radius * angle**2 * (1 + BOUND_SLACK)
    )


vectors = hnp.arrays(np.float64, (3,), elements=st.floats(-3.0, 3.0))
unit_sizes = st.floats(0.05, 5.0)


@st.composite
def any_path(draw: st.DrawFn) -> Path:
    kind = draw(st.sampled_from(["line", "arc", "ellipse", "eight", "polyline"]))
    center = draw(vectors)
    if kind == "line":
        start, end = draw(vectors), draw(vectors)
        assume(np.linalg.norm(end - start) > 1e-3)
        return Line(start, end)
    if kind == "polyline":
        points = draw(
            hnp.arrays(np.float64, (draw(st.integers(2, 6)), 3), elements=st.floats(-3.0, 3.0))
        )
        assume(np.all(np.linalg.norm(np.diff(points, axis=0), axis=1) > 1e-3))
        return Polyline(points)
    normal = draw(vectors)
    assume(np.linalg.norm(normal) > 1e-2)
    if kind == "arc":
        start = draw(vectors)
        offset = start - center
        n = normal / np.linalg.norm(normal)
        assume(np.linalg.norm(offset - n * (offset @ n)) > 1e-2)
        angle = draw(st.one_of(st.floats(-8.0, -1e-3), st.floats(1e-3, 8.0)))
        return Arc(center, start, angle, normal=normal)
    if kind == "ellipse":
        b = draw(st.one_of(st.just(0.0), unit_sizes))
        turns = draw(st.one_of(st.floats(-2.0, -0.05), st.floats(0.05, 2.0)))
        return Ellipse(
            center,
            draw(unit_sizes),
            b,
            turns=turns,
            phase=draw(st.floats(-np.pi, np.pi)),
            normal=normal,
            x_axis=None,
        )
    return FigureEight(center, draw(unit_sizes), draw(unit_sizes), normal=normal, x_axis=None)


@FEW
@given(path=any_path())
def test_property_bounds_hold_for_random_paths(path):
    assert_bounds_hold(path)


@FEW
@given(path=any_path(), u=st.floats(0.05, 0.95))
def test_property_derivatives_match_central_differences(path, u):
    if isinstance(path, Polyline):
        assume(np.abs(path.knots - u).min() > 10 * FD_STEP)
    for order in (1, 2):
        support.assert_state(
            path.evaluate(u, order),
            central_difference(path, np.array([u]), order),
            rtol=FINITE_DIFFERENCE,
        )


# ------------------------------------------------------------------------- end points
def test_line_end_points_and_2d_points():
    line = Line([1.0, 2.0, 3.0], [-4.0, 0.5, 7.0])
    np.testing.assert_array_equal(line.start, [1.0, 2.0, 3.0])
    np.testing.assert_allclose(line.end, [-4.0, 0.5, 7.0], atol=GEOMETRY)
    np.testing.assert_allclose(line.evaluate(0.5)[0], [-1.5, 1.25, 5.0], atol=GEOMETRY)
    flat = paths()["line2d"]
    np.testing.assert_array_equal(flat.start, [0.5, -1.0, 0.0])
    np.testing.assert_allclose(flat.end, [-2.0, 3.0, 0.0], atol=GEOMETRY)


def test_arc_end_is_the_start_turned_about_the_axis():
    center, start, angle = np.array([1.0, 0.0, 0.0]), np.array([2.0, 0.0, 0.5]), 1.5 * np.pi
    normal = np.array([0.0, 1.0, 1.0]) / np.sqrt(2)
    arc = Arc(center, start, angle, normal=normal * 3.0)  # any length of normal
    np.testing.assert_allclose(arc.start, start, atol=GEOMETRY)
    expected = center + axis_rotation(normal, angle) @ (start - center)
    np.testing.assert_allclose(arc.end, expected, atol=GEOMETRY)


def test_ellipse_figure_eight_and_polyline_end_points():
    ellipse = Ellipse([1.0, 2.0, 3.0], 0.5, 0.25, turns=0.25, phase=0.3)
    np.testing.assert_allclose(
        ellipse.start, [1 + 0.5 * np.cos(0.3), 2 + 0.25 * np.sin(0.3), 3], atol=GEOMETRY
    )
    phi = 0.3 + np.pi / 2
    np.testing.assert_allclose(
        ellipse.end, [1 + 0.5 * np.cos(phi), 2 + 0.25 * np.sin(phi), 3], atol=GEOMETRY
    )
    eight = paths()["eight"]
    np.testing.assert_allclose(eight.start, [0.5, 0.0, 0.0], atol=GEOMETRY)
    np.testing.assert_allclose(eight.end, [0.5, 0.0, 0.0], atol=GEOMETRY)
    polyline = paths()["polyline"]
    np.testing.assert_array_equal(polyline.start, polyline.waypoints[0])
    np.testing.assert_array_equal(polyline.end, polyline.waypoints[-1])


# ------------------------------------------------------------------------------- arcs
@pytest.mark.parametrize(
    ("center", "start", "angle", "normal"),
    [
        ([1.0, 0.0, 0.0], [2.0, 0.0, 0.5], 1.5 * np.pi, [0.0, 1.0, 1.0]),
        ([0.0, 0.0, 0.0], [0.0, 0.7, 0.0], -2.5 * np.pi, [0.0, 0.0, 1.0]),
        ([0.3, -0.2, 1.0], [1.0, 1.0, 1.0], 0.1, [2.0, -1.0, 0.5]),
        ([0.0, 0.0], [3.0, 0.0], 2 * np.pi, [0.0, 0.0, -1.0]),
    ],
)
def test_arc_stays_at_its_radius_from_the_axis_and_sweeps_its_angle(center, start, angle, normal):
    arc = Arc(center, start, angle, normal=normal)
    c = np.append(center, 0.0) if len(center) == 2 else np.asarray(center)
    s = np.append(start, 0.0) if len(start) == 2 else np.asarray(start)
    n = np.asarray(normal) / np.linalg.norm(normal)
    offset = s - c
    radial = offset - n * (offset @ n)
    assert arc.radius == pytest.approx(np.linalg.norm(radial), rel=support.ROUNDING)
    points = arc.evaluate(np.linspace(0.0, 1.0, GRID))
    relative = points - c
    axial = relative @ n
    distance = np.linalg.norm(relative - axial[:, np.newaxis] * n, axis=1)
    np.testing.assert_allclose(distance, arc.radius, rtol=GEOMETRY)
    # In the plane through the start, perpendicular to the axis.
    np.testing.assert_allclose(axial, offset @ n, atol=GEOMETRY)
    swept = signed_sweep(points, c + n * (offset @ n), n)
    assert swept == pytest.approx(angle, rel=GEOMETRY)


# --------------------------------------------------------------------------- ellipses
def test_ellipse_points_satisfy_the_ellipse_equation():
    center = np.array([0.2, -0.1, 0.3])
    a, b = 0.6, 0.4
    ellipse = Ellipse(
        center, a, b, turns=1.25, phase=-0.7, normal=[0.0, 0.0, 2.0], x_axis=[1.0, 1.0, 0.4]
    )
    e1 = np.array([1.0, 1.0, 0.0]) / np.sqrt(2)  # x_axis projected on the plane
    e2 = np.cross([0.0, 0.0, 1.0], e1)
    points = ellipse.evaluate(np.linspace(0.0, 1.0, 501)) - center
    np.testing.assert_allclose(points @ [0.0, 0.0, 1.0], 0.0, atol=GEOMETRY)
    np.testing.assert_allclose((points @ e1 / a) ** 2 + (points @ e2 / b) ** 2, 1.0, atol=GEOMETRY)
    np.testing.assert_allclose(
        points[0], a * np.cos(-0.7) * e1 + b * np.sin(-0.7) * e2, atol=GEOMETRY
    )


def test_ellipse_default_plane_without_x_axis_is_orthonormal():
    normal = np.array([0.9, 0.1, 0.2])
    ellipse = Ellipse([0.0, 0.0, 0.0], 1.0, 1.0, normal=normal, x_axis=None)
    points = ellipse.evaluate(np.linspace(0, 1, 201))
    # A circle of radius 1 in the plane normal to `normal`.
    np.testing.assert_allclose(np.linalg.norm(points, axis=1), 1.0, atol=GEOMETRY)
    np.testing.assert_allclose(points @ (normal / np.linalg.norm(normal)), 0.0, atol=GEOMETRY)


@pytest.mark.parametrize(
    ("center", "a", "turns", "phase", "x_axis"),
    [
        ([0.0, 1.2, 0.0], 0.9, 1.0, 0.0, [1.0, 0.0, 0.0]),
        ([0.5, -0.5, 2.0], 1.7, 2.0, 0.4, [1.0, 2.0, 0.0]),
        ([0.0, 0.0, 0.0], 0.3, -0.5, -1.0, [0.0, -1.0, 0.0]),
    ],
)
def test_ellipse_with_b_zero_is_a_harmonic_segment(center, a, turns, phase, x_axis):
    segment = Ellipse(center, a, 0.0, turns=turns, phase=phase, x_axis=x_axis)
    u = np.linspace(0.0, 1.0, 401)
    direction = np.asarray(x_axis) / np.linalg.norm(x_axis)
    phi = phase + 2 * np.pi * turns * u
    expected = np.asarray(center) + (a * np.cos(phi))[:, np.newaxis] * direction
    np.testing.assert_allclose(segment.evaluate(u), expected, atol=GEOMETRY)
    w = 2 * np.pi * turns
    np.testing.assert_allclose(
        segment.evaluate(u, 1), (-a * w * np.sin(phi))[:, None] * direction, atol=GEOMETRY * abs(w)
    )
    np.testing.assert_allclose(
        segment.evaluate(u, 2), (-a * w**2 * np.cos(phi))[:, None] * direction, atol=GEOMETRY * w**2
    )


def test_seed002_segment_formula():
    # Seed 002: x = 0.9 cos(2 pi t / T) sqrt((L1 + L2)^2 - h^2), y = h, with u = t / T.
    l1, l2 = 1.0, 0.8
    h = 2.0 / 3.0 * (l1 + l2)
    amplitude = 0.9 * np.sqrt((l1 + l2) ** 2 - h**2)
    segment = Ellipse([0.0, h, 0.0], amplitude, 0.0)
    u = np.linspace(0.0, 1.0, 1001)
    points = segment.evaluate(u)
    np.testing.assert_allclose(points[:, 0], amplitude * np.cos(2 * np.pi * u), atol=GEOMETRY)
    np.testing.assert_allclose(points[:, 1], h, atol=GEOMETRY)
    np.testing.assert_allclose(points[:, 2], 0.0, atol=GEOMETRY)


# ------------------------------------------------------------------------ figure eight
@pytest.mark.parametrize(("width", "height"), [(2.0, 1.0), (0.4, 3.0), (1.0, 1.0)])
def test_figure_eight_matches_its_formula(width, height):
    center = np.array([0.5, -0.25, 1.5])
    eight = FigureEight(center, width, height)
    u = np.linspace(0.0, 1.0, 1001)
    points = eight.evaluate(u) - center
    np.testing.assert_allclose(points[:, 0], width / 2 * np.sin(2 * np.pi * u), atol=GEOMETRY)
    np.testing.assert_allclose(points[:, 1], height / 2 * np.sin(4 * np.pi * u), atol=GEOMETRY)
    np.testing.assert_allclose(points[:, 2], 0.0, atol=GEOMETRY)
    # It crosses itself at the center at u = 1/2 and spans exactly W by H.
    np.testing.assert_allclose(eight.evaluate(0.5)[0], center, atol=GEOMETRY)
    assert np.ptp(points[:, 0]) == pytest.approx(width, rel=1e-6)
    assert np.ptp(points[:, 1]) == pytest.approx(height, rel=1e-6)


def test_figure_eight_in_another_plane():
    # Normal +y, width along x: the in-plane "y" direction is n x e1 = -z.
    eight = FigureEight([0.0, 0.3, 1.0], 0.8, 1.4, normal=[0.0, 1.0, 0.0], x_axis=[1.0, 0.0, 0.0])
    u = np.linspace(0.0, 1.0, 201)
    points = eight.evaluate(u)
    np.testing.assert_allclose(points[:, 0], 0.4 * np.sin(2 * np.pi * u), atol=GEOMETRY)
    np.testing.assert_allclose(points[:, 1], 0.3, atol=GEOMETRY)
    np.testing.assert_allclose(points[:, 2], 1.0 - 0.7 * np.sin(4 * np.pi * u), atol=GEOMETRY)


# --------------------------------------------------------------------------- polylines
@pytest.mark.parametrize("name", ["polyline", "polyline2d"])
def test_polyline_passes_through_its_waypoints_at_its_knots(name):
    path = paths()[name]
    np.testing.assert_allclose(path.evaluate(path.knots), path.waypoints, atol=GEOMETRY)
    lengths = np.linalg.norm(np.diff(path.waypoints, axis=0), axis=1)
    assert path.length == pytest.approx(lengths.sum(), rel=support.ROUNDING)
    np.testing.assert_allclose(
        path.knots, np.concatenate([[0], np.cumsum(lengths)]) / path.length, atol=support.ROUNDING
    )
    assert path.knots[0] == 0.0 and path.knots[-1] == pytest.approx(1.0, abs=support.ROUNDING)


def test_polyline_2d_waypoints_lie_at_z_zero():
    path = paths()["polyline2d"]
    np.testing.assert_array_equal(path.waypoints[:, 2], 0.0)
    assert path.length == pytest.approx(5.0 + 4.0, rel=support.ROUNDING)
    np.testing.assert_allclose(path.knots, [0.0, 5.0 / 9.0, 1.0], atol=support.ROUNDING)


def test_polyline_parameter_is_proportional_to_distance():
    path = paths()["polyline"]
    u = np.linspace(0.0, 1.0, 997)
    points = path.evaluate(u)
    # Distance travelled to each point: whole segments before it plus the part of its own.
    segment = np.clip(np.searchsorted(path.knots, u, side="right") - 1, 0, len(path.knots) - 2)
    lengths = np.linalg.norm(np.diff(path.waypoints, axis=0), axis=1)
    before = np.concatenate([[0.0], np.cumsum(lengths)])[segment]
    travelled = before + np.linalg.norm(points - path.waypoints[segment], axis=1)
    np.testing.assert_allclose(travelled, u * path.length, atol=GEOMETRY * path.length)
    # Constant speed |dp/du| = length on every segment.
    np.testing.assert_allclose(
        np.linalg.norm(path.evaluate(u, 1), axis=1), path.length, rtol=support.ROUNDING
    )
    np.testing.assert_array_equal(path.evaluate(u, 2), 0.0)


def test_polyline_may_revisit_a_waypoint():
    path = Polyline([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
    np.testing.assert_allclose(path.evaluate(0.5)[0], [1.0, 0.0, 0.0], atol=GEOMETRY)
    np.testing.assert_allclose(path.end, [0.0, 0.0, 0.0], atol=GEOMETRY)


# -------------------------------------------------------------------------- bad input
LINE = Line([0.0, 0.0, 0.0], [1.0, 0.0, 0.0])


@pytest.mark.parametrize(
    ("make", "message"),
    [
        (lambda: Line([0.0, 0.0, np.nan], [1.0, 0.0, 0.0]), "start must be finite"),
        (lambda: Line([0.0, 0.0, 0.0], [np.inf, 0.0, 0.0]), "end must be finite"),
        (lambda: Line([0.0, 0.0, 0.0, 0.0], [1.0, 0.0, 0.0]), "start must be a point"),
        (lambda: Line([0.0, 0.0, 0.0], [[1.0, 0.0, 0.0]]), "end must be a point"),
        (lambda: Line([0.0], [1.0, 0.0, 0.0]), "start must be a point"),
        (lambda: Line("origin", [1.0, 0.0, 0.0]), "start must be numeric, got 'origin'"),
        (lambda: Arc([0.0, 0.0, 0.0], [0.0, 0.0, 1.0], 1.0), "radius would be 0"),
        (lambda: Arc([1.0, 1.0, 0.0], [1.0, 1.0, 0.0], 1.0), "radius would be 0"),
        (lambda: Arc([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], 0.0), "angle must be non-zero"),
        (lambda: Arc([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], np.nan), "angle must be finite"),
        (lambda: Arc([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 2.0]), "angle must be a single"),
        (lambda: Arc([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], 1.0, normal=[0, 0, 0]), "non-zero vector"),
        (lambda: Arc([0.0, np.nan, 0.0], [1.0, 0.0, 0.0], 1.0), "center must be finite"),
        (lambda: Ellipse([0.0, 0.0, 0.0], 0.0, 0.5), "a must be > 0"),
        (lambda: Ellipse([0.0, 0.0, 0.0], -1.0, 0.5), "a must be > 0"),
        (lambda: Ellipse([0.0, 0.0, 0.0], 1.0, -0.1), "b must be >= 0"),
        (lambda: Ellipse([0.0, 0.0, 0.0], 1.0, np.nan), "b must be finite"),
        (lambda: Ellipse([0.0, 0.0, 0.0], 1.0, 0.5, turns=0), "turns must be non-zero"),
        (lambda: Ellipse([0.0, 0.0, 0.0], 1.0, 0.5, turns=np.inf), "turns must be finite"),
        (lambda: Ellipse([0.0, 0.0, 0.0], 1.0, 0.5, phase=np.nan), "phase must be finite"),
        (lambda: Ellipse([0, 0, 0], 1.0, 0.5, x_axis=[0, 0, 1]), "must not be parallel"),
        (lambda: Ellipse([0, 0, 0], 1.0, 0.5, x_axis=[0, 0, -3]), "must not be parallel"),
        (lambda: Ellipse([0, 0, 0], 1.0, 0.5, normal=[0, 0, 0]), "normal must be a non-zero"),
        (lambda: Ellipse([0.0, 0.0], 1.0, 0.5, x_axis=[1, 0, 0, 0]), "x_axis must be a point"),
        (lambda: FigureEight([0.0, 0.0, 0.0], 0.0, 1.0), "width must be > 0"),
        (lambda: FigureEight([0.0, 0.0, 0.0], 1.0, -1.0), "height must be > 0"),
        (lambda: FigureEight([0, 0, 0], 1.0, 1.0, normal=[1, 0, 0], x_axis=[2, 0, 0]), "parallel"),
        (lambda: Polyline([[0.0, 0.0, 0.0]]), "k >= 2"),
        (lambda: Polyline([0.0, 1.0, 2.0]), "waypoints must have shape"),
        (lambda: Polyline(np.zeros((3, 4))), "waypoints must have shape"),
        (lambda: Polyline([[0.0, 0.0], [1.0, np.nan]]), "waypoints must be finite"),
        (lambda: Polyline([[0, 0, 0], [1, 0, 0], [1, 0, 0]]), "waypoints 1 and 2 coincide"),
        (lambda: Polyline([[0.0, 0.0], [0.0, 0.0]]), "waypoints 0 and 1 coincide"),
        (lambda: LINE.evaluate(0.5, order=1.5), "order must be a whole number >= 0 for a path"),
        (lambda: LINE.evaluate(0.5, order=-1), "order must be a whole number >= 0 for a path"),
        (lambda: LINE.evaluate([0.5, np.nan]), "u must be finite"),
        (lambda: paths()["arc"].evaluate(np.inf, 1), "u must be finite"),
        (lambda: paths()["polyline"].evaluate(np.nan, 2), "u must be finite"),
    ],
)
def test_bad_input_raises_invalid_input_error(make, message):
    with pytest.raises(InvalidInputError, match=message) as excinfo:
        make()
    assert type(excinfo.value) is InvalidInputError
