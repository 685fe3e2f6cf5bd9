"""Tests of trajkit.Samples: validation and exact CSV / JSON / NPZ round trips."""

from __future__ import annotations

import json
import tempfile
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import trajkit as tk
from trajkit import InvalidInputError, Samples

FIELDS = ("q", "qd", "qdd", "qddd")


def make(n: int = 3, ndof: int = 2, **kwargs: object) -> Samples:
    """Small valid samples with distinct values in every array."""
    t = np.arange(n, dtype=float) * 0.5
    arrays = [np.arange(n * ndof, dtype=float).reshape(n, ndof) + 10.0 * k for k in range(4)]
    return Samples(t, *arrays, **kwargs)  # type: ignore[arg-type]


def bits(array: np.ndarray) -> np.ndarray:
    """The raw 64-bit patterns: equality here is bit for bit (it tells -0.0 from 0.0)."""
    return np.ascontiguousarray(array, dtype=np.float64).view(np.uint64)


def assert_same_samples(actual: Samples, expected: Samples) -> None:
    for name in ("t", *FIELDS):
        a, e = getattr(actual, name), getattr(expected, name)
        assert a.shape == e.shape, name
        assert np.array_equal(a, e), name
        np.testing.assert_array_equal(bits(a), bits(e), err_msg=name)
    assert actual.unit == expected.unit
    assert actual.names == expected.names


# --------------------------------------------------------------- construction


def test_construction_and_defaults() -> None:
    s = make(4, 3)
    assert len(s) == 4
    assert s.ndof == 3
    assert s.unit == "rad"
    assert s.names == ("q1", "q2", "q3")
    assert s.t.dtype == np.float64
    assert s.q.shape == (4, 3)


def test_one_dimensional_arrays_mean_one_joint() -> None:
    s = Samples([0.0, 1.0], [1.0, 2.0], [0.0, 0.0], [0.0, 0.0], [0.0, 0.0], unit="m")
    assert s.q.shape == (2, 1)
    assert s.ndof == 1
    assert s.names == ("q1",)
    assert s.unit == "m"


def test_arrays_are_read_only_copies() -> None:
    q = np.zeros((2, 1))
    s = Samples([0.0, 1.0], q, q, q, q, names=["shoulder"])
    q[0, 0] = 5.0
    assert s.q[0, 0] == 0.0
    assert s.names == ("shoulder",)  # a list becomes a tuple
    for name in ("t", *FIELDS):
        array = getattr(s, name)
        assert not array.flags.writeable, name
        with pytest.raises(ValueError, match="read-only"):
            array[0] = 1.0
    with pytest.raises(AttributeError):
        s.unit = "m"  # type: ignore[misc]


_GOOD = np.zeros((3, 2))


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"t": [[0.0, 1.0, 2.0]]}, r"t must be a non-empty 1-D array, got shape \(1, 3\)"),
        ({"t": []}, r"t must be a non-empty 1-D array"),
        ({"t": [0.0, 1.0, 1.0]}, r"t must be strictly increasing"),
        ({"t": [0.0, 2.0, 1.0]}, r"t must be strictly increasing"),
        ({"t": [0.0, np.nan, 1.0]}, r"t must be finite"),
        ({"t": ["a", "b", "c"]}, r"t must be numeric"),
        ({"q": np.zeros((4, 2))}, r"q must have shape \(3, ndof\), got shape \(4, 2\)"),
        ({"qd": np.zeros((3, 2, 1))}, r"qd must have shape \(3, ndof\)"),
        ({"qdd": np.zeros((3, 3))}, r"qdd has 3 joints but q has 2"),
        ({"qddd": np.full((3, 2), np.inf)}, r"qddd must be finite"),
        ({"unit": ""}, r"unit must be a short text"),
        ({"unit": "rad]"}, r"unit must be a short text"),
        ({"unit": "[rad"}, r"unit must be a short text"),
        ({"unit": "rad,m"}, r"unit must be a short text"),
        ({"unit": 5}, r"unit must be a short text"),
        ({"names": ("a",)}, r"names gives 1 labels for 2 joints"),
        ({"names": ("a", "b", "c")}, r"names gives 3 labels for 2 joints"),
        ({"names": ("1q", "q2")}, r"joint name '1q' must start with a letter"),
        ({"names": ("q 1", "q2")}, r"joint name 'q 1'"),
        ({"names": ("q1", "")}, r"joint name ''"),
        ({"names": ("q1", "q,2")}, r"joint name 'q,2'"),
        ({"names": ("q1", "q[2]")}, r"joint name 'q\[2\]'"),
        ({"names": ("q1", 2)}, r"joint name 2"),
    ],
)
def test_invalid_samples_are_refused(kwargs: dict, match: str) -> None:
    arguments: dict[str, object] = {
        "t": [0.0, 1.0, 2.0],
        **{name: _GOOD for name in FIELDS},
    }
    arguments.update(kwargs)
    with pytest.raises(InvalidInputError, match=match) as excinfo:
        Samples(**arguments)  # type: ignore[arg-type]
    assert type(excinfo.value) is InvalidInputError


def test_a_joint_name_with_a_trailing_newline_is_refused() -> None:
    with pytest.raises(InvalidInputError, match=r"joint name"):
        make(2, 1, names=("q1\n",))


@pytest.mark.parametrize("unit", ["r\nad", "rad\r", "rad\x00", "rad\u2028"])
def test_a_unit_with_control_characters_is_refused(unit: str) -> None:
    with pytest.raises(InvalidInputError, match=r"unit must be a short text"):
        make(2, 1, unit=unit)


def test_zero_joints_are_refused() -> None:
    empty = np.zeros((2, 0))
    with pytest.raises(InvalidInputError, match=r"joint"):
        Samples([0.0, 1.0], empty, empty, empty, empty)


# ------------------------------------------------------------------ round trips

# Every finite float: subnormals, +-0.0, the largest and smallest magnitudes.
finite = st.floats(allow_nan=False, allow_infinity=False)
name_st = st.from_regex(r"[A-Za-z_][A-Za-z0-9_.-]{0,10}", fullmatch=True)
unit_st = st.text(
    alphabet=st.sampled_from(
        "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789/^*.-_ %°µ"
    ),
    min_size=1,
    max_size=8,
)


@st.composite
def samples_st(draw: st.DrawFn) -> Samples:
    n = draw(st.integers(1, 12))
    ndof = draw(st.integers(1, 4))
    # unique=True compares with ==, so -0.0 and 0.0 never both appear: sorted is increasing.
    t = np.sort(draw(hnp.arrays(np.float64, (n,), elements=finite, unique=True)))
    arrays = [draw(hnp.arrays(np.float64, (n, ndof), elements=finite)) for _ in FIELDS]
    names = draw(st.one_of(st.just(()), st.lists(name_st, min_size=ndof, max_size=ndof)))
    unit = draw(unit_st)
    return Samples(t, *arrays, unit=unit, names=tuple(names))


FORMATS: dict[str, tuple[Callable, Callable]] = {
    "csv": (Samples.to_csv, Samples.from_csv),
    "json": (Samples.to_json, Samples.from_json),
    "npz": (Samples.to_npz, Samples.from_npz),
}


@pytest.mark.parametrize("fmt", sorted(FORMATS))
@settings(max_examples=100)
@given(samples=samples_st())
def test_round_trip_is_exact(fmt: str, samples: Samples) -> None:
    write, read = FORMATS[fmt]
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / f"samples.{fmt}"
        assert write(samples, path) == path
        back = read(path)
        assert_same_samples(back, samples)
        # Nothing else is left in the folder (no temporary files).
        assert sorted(p.name for p in Path(folder).iterdir()) == [path.name]


@pytest.mark.parametrize("fmt", sorted(FORMATS))
def test_round_trip_of_extreme_values(fmt: str, tmp_path: Path) -> None:
    tiny = np.nextafter(0.0, 1.0)  # smallest subnormal
    t = np.array([-1e300, -0.0, 5e-324 * 3, 0.1, 1.7976931348623157e308])
    column = np.array([-0.0, tiny, -2.2250738585072014e-308, 1 / 3, np.pi * 1e200])[:, None]
    samples = Samples(t, column, -column, column * 0.5, column[::-1], unit="m", names=("x",))
    write, read = FORMATS[fmt]
    path = write(samples, tmp_path / f"extreme.{fmt}")
    assert_same_samples(read(path), samples)


def test_csv_header_names_the_units(tmp_path: Path) -> None:
    path = make(2, 2).to_csv(tmp_path / "s.csv")
    lines = path.read_text(encoding="utf-8").splitlines()
    assert lines[0] == (
        "t [s],q1 [rad],q2 [rad],q1_vel [rad/s],q2_vel [rad/s],"
        "q1_acc [rad/s^2],q2_acc [rad/s^2],q1_jerk [rad/s^3],q2_jerk [rad/s^3]"
    )
    assert len(lines) == 3
    assert [float(x) for x in lines[1].split(",")] == [0, 0, 1, 10, 11, 20, 21, 30, 31]
    named = make(1, 1, unit="m", names=("slide",)).to_csv(tmp_path / "m.csv")
    header = named.read_text(encoding="utf-8").splitlines()[0]
    assert header == "t [s],slide [m],slide_vel [m/s],slide_acc [m/s^2],slide_jerk [m/s^3]"


def test_json_document_layout(tmp_path: Path) -> None:
    path = make(2, 1, names=("j",)).to_json(tmp_path / "s.json")
    document = json.loads(path.read_text(encoding="utf-8"))
    assert document["format"] == "trajkit.samples"
    assert document["version"] == 1
    assert document["unit"] == "rad"
    assert document["names"] == ["j"]
    assert document["t"] == [0.0, 0.5]
    assert document["qd"] == [[10.0], [11.0]]


def test_writing_replaces_an_existing_file(tmp_path: Path) -> None:
    path = tmp_path / "s.csv"
    path.write_text("old content that is longer than the new file " * 100)
    make(2, 1).to_csv(path)
    assert_same_samples(Samples.from_csv(path), make(2, 1))


@pytest.mark.parametrize("fmt", sorted(FORMATS))
def test_writing_into_a_missing_folder_fails_cleanly(fmt: str, tmp_path: Path) -> None:
    write, _ = FORMATS[fmt]
    target = tmp_path / "missing" / f"s.{fmt}"
    with pytest.raises(OSError):
        write(make(), target)
    assert not target.parent.exists()
    assert list(tmp_path.iterdir()) == []


# ------------------------------------------------------------ malformed files

HEADER = "t [s],q1 [rad],q1_vel [rad/s],q1_acc [rad/s^2],q1_jerk [rad/s^3]"


@pytest.mark.parametrize(
    ("content", "match"),
    [
        ("", r"empty file, expected a header line"),
        (HEADER + "\n", r"no samples after the header"),
        (HEADER + "\n\n   \n", r"no samples after the header"),
        ("time,q1,q1_vel,q1_acc,q1_jerk\n0,0,0,0,0\n", r"line 1: expected 't \[s\]'"),
        ("t [s],q1 [rad],q1_vel [rad/s]\n0,0,0\n", r"line 1: .*got 3 columns"),
        (
            "t [s],q1 [rad],q1_velocity [rad/s],q1_acc [rad/s^2],q1_jerk [rad/s^3]\n",
            r"line 1: column 3 header 'q1_velocity \[rad/s\]' is not '<joint>_vel",
        ),
        (
            "t [s],q1 [rad],q2_vel [rad/s],q1_acc [rad/s^2],q1_jerk [rad/s^3]\n",
            r"line 1: column 3 header 'q2_vel \[rad/s\]'",
        ),
        (
            "t [s],q1 [rad],q1_vel [rad/min],q1_acc [rad/s^2],q1_jerk [rad/s^3]\n",
            r"line 1: column 3 has unit \[rad/min\], expected \[rad/s\]",
        ),
        (
            "t [s],q1 rad,q1_vel [rad/s],q1_acc [rad/s^2],q1_jerk [rad/s^3]\n",
            r"line 1: column 2 header 'q1 rad'",
        ),
        (HEADER + "\n0,0,0,0,0\n1,0,0,0\n", r"line 3: 4 values, expected 5"),
        (HEADER + "\n0,0,0,0,0,0\n1,0,0,0,0,0\n", r"line 2: 6 values, expected 5"),
        (HEADER + "\n0,0,0,0,0\n\n1,0,abc,0,0\n", r"line 4: 'abc' is not a number"),
        (HEADER + "\n0,0,0,0,0\n0,0,0,0,0\n", r"t must be strictly increasing"),
        (HEADER + "\n0,0,0,0,0\n1,nan,0,0,0\n", r"q must be finite"),
    ],
)
def test_malformed_csv_is_refused_with_the_line(content: str, match: str, tmp_path: Path) -> None:
    path = tmp_path / "bad.csv"
    path.write_text(content, encoding="utf-8")
    with pytest.raises(InvalidInputError, match=match) as excinfo:
        Samples.from_csv(path)
    assert str(path) in str(excinfo.value)


def test_unreadable_csv_is_refused(tmp_path: Path) -> None:
    binary = tmp_path / "binary.csv"
    binary.write_bytes(b"\xff\xfe\x00garbage")
    with pytest.raises(InvalidInputError, match=r"cannot read samples file .*binary.csv"):
        Samples.from_csv(binary)
    with pytest.raises(InvalidInputError, match=r"cannot read samples file .*absent.csv"):
        Samples.from_csv(tmp_path / "absent.csv")


def _json_document() -> dict:
    return {
        "format": "trajkit.samples",
        "version": 1,
        "unit": "rad",
        "names": ["q1"],
        "t": [0.0, 1.0],
        "q": [[0.0], [1.0]],
        "qd": [[0.0], [1.0]],
        "qdd": [[0.0], [1.0]],
        "qddd": [[0.0], [1.0]],
    }


@pytest.mark.parametrize(
    ("change", "match"),
    [
        (lambda d: "not json at all", r"cannot read samples file"),
        (lambda d: [1, 2, 3], r"not a trajkit samples document \(format key\)"),
        (lambda d: {**d, "format": "other"}, r"not a trajkit samples document"),
        (
            lambda d: {k: v for k, v in d.items() if k not in ("q", "names")},
            r"missing key\(s\) q, names",
        ),
        (lambda d: {**d, "t": [1.0, 0.0]}, r"t must be strictly increasing"),
        (lambda d: {**d, "qd": [[0.0]]}, r"qd must have shape \(2, ndof\)"),
        (lambda d: {**d, "unit": None}, r"unit must be a short text"),
        (lambda d: {**d, "names": ["1x"]}, r"joint name '1x'"),
        (lambda d: {**d, "t": "abc"}, r"t must be numeric"),
    ],
)
def test_malformed_json_is_refused(change: Callable, match: str, tmp_path: Path) -> None:
    path = tmp_path / "bad.json"
    document = change(_json_document())
    path.write_text(document if isinstance(document, str) else json.dumps(document))
    with pytest.raises(InvalidInputError, match=match) as excinfo:
        Samples.from_json(path)
    assert str(path) in str(excinfo.value)


@pytest.mark.parametrize("names", [None, 5])
def test_json_names_that_are_not_a_list_are_refused(names: object, tmp_path: Path) -> None:
    path = tmp_path / "bad.json"
    path.write_text(json.dumps({**_json_document(), "names": names}))
    with pytest.raises(InvalidInputError, match=r"names"):
        Samples.from_json(path)


def _write_npz(path: Path, **overrides: object) -> None:
    arrays: dict[str, object] = {
        "t": np.array([0.0, 1.0]),
        **{name: np.array([[0.0], [1.0]]) for name in FIELDS},
        "unit": np.array("rad"),
        "names": np.array(["q1"]),
    }
    arrays.update(overrides)
    np.savez(path, **{k: v for k, v in arrays.items() if v is not None})  # type: ignore[arg-type]


def test_malformed_npz_is_refused(tmp_path: Path) -> None:
    text = tmp_path / "text.npz"
    text.write_text("this is not a zip archive")
    with pytest.raises(InvalidInputError, match=r"cannot read samples file .*text.npz"):
        Samples.from_npz(text)
    empty = tmp_path / "empty.npz"
    empty.write_bytes(b"")
    with pytest.raises(InvalidInputError, match=r"cannot read samples file .*empty.npz"):
        Samples.from_npz(empty)
    with pytest.raises(InvalidInputError, match=r"cannot read samples file .*absent.npz"):
        Samples.from_npz(tmp_path / "absent.npz")
    partial = tmp_path / "partial.npz"
    _write_npz(partial, q=None, names=None)
    with pytest.raises(InvalidInputError, match=r"partial.npz: missing array\(s\) q, names"):
        Samples.from_npz(partial)
    pickled = tmp_path / "pickled.npz"
    _write_npz(pickled, names=np.array([{"a": 1}], dtype=object))
    with pytest.raises(InvalidInputError, match=r"cannot read samples file .*pickled.npz"):
        Samples.from_npz(pickled)
    shapes = tmp_path / "shapes.npz"
    _write_npz(shapes, qdd=np.zeros((3, 1)))
    with pytest.raises(InvalidInputError, match=r"shapes.npz: qdd must have shape \(2, ndof\)"):
        Samples.from_npz(shapes)
    # A valid archive written by hand reads back.
    good = tmp_path / "good.npz"
    _write_npz(good)
    assert Samples.from_npz(good).names == ("q1",)


def test_npz_with_scalar_names_is_refused_or_read(tmp_path: Path) -> None:
    path = tmp_path / "scalar_names.npz"
    _write_npz(path, names=np.array("q1"))
    try:
        samples = Samples.from_npz(path)
    except InvalidInputError:
        return
    assert samples.names == ("q1",)


def test_json_and_npz_keep_the_plans_metadata(tmp_path):
    plan = tk.trapezoidal(np.zeros(2), [1.0, 0.5], 1.0, 2.0, sync="phase", period=0.002)
    samples = plan.sample(0.01)
    assert samples.metadata["sync"] == "phase" and samples.metadata["period"] == 0.002
    for write, read, name in ((samples.to_json, tk.Samples.from_json, "s.json"),
                              (samples.to_npz, tk.Samples.from_npz, "s.npz")):  # fmt: skip
        back = read(write(tmp_path / name))
        assert back.metadata["phase_times"] == np.asarray(plan.info["phase_times"]).tolist()
        assert back.metadata["limiting_joint"] == plan.info["limiting_joint"]
    # Non-finite values and other objects become strings; tuples become lists.
    from trajkit.samples import plain

    assert plain({"a": (1, np.inf), "b": np.float64(2.5), "c": object}) == {
        "a": [1, "inf"],
        "b": 2.5,
        "c": str(object),
    }
