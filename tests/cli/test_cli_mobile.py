"""``trajkit mobile``: a plan that breaks a limit exits 1, as ``trajkit run`` does."""

from __future__ import annotations

import numpy as np
import pytest

from trajkit.cli import EXIT_LIMITS_BROKEN, main

BROKEN = "trajkit: the plan breaks a limit (see the limit check above)\n"


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    status = main(["mobile", *argv])
    captured = capsys.readouterr()
    return status, captured.out, captured.err


def test_a_twist_beyond_the_jackal_limits_exits_1_and_still_writes(capsys, tmp_path):
    # 5 m/s against the Jackal's 2 m/s; its wheels at 50.5 and 51.5 rad/s against 20.4.
    csv = tmp_path / "twist.csv"
    status, out, err = run(capsys, "twist", "10", "5", "10", "15", "--csv", str(csv))
    assert status == EXIT_LIMITS_BROKEN == 1
    assert err == BROKEN
    assert "limit check: 3 violation(s)" in out
    assert "velocity of base reaches 5 at t=0 s, beyond the bound 2" in out
    assert f"wrote {csv}" in out
    table = np.loadtxt(csv, delimiter=",", skiprows=1)
    assert table[-1, 0] == 15.0  # written in full although a limit is broken


def test_figure8_vmax_without_fit_is_checked_and_exits_1(capsys):
    # The curve's own timing peaks at 0.444288 m/s; --vmax 0.05 is enforced by the check.
    status, out, err = run(capsys, "figure8", "--vmax", "0.05")
    assert status == 1
    assert err == BROKEN
    assert "velocity of base reaches 0.444288 at t=0 s, beyond the bound 0.05" in out
    assert "--fit slows the curve down uniformly until every limit holds" in out


def test_figure8_vmax_with_fit_meets_it_and_exits_0(capsys):
    status, out, err = run(capsys, "figure8", "--vmax", "0.05", "--fit")
    assert status == 0, err
    assert err == ""
    assert "(set by the velocity limit)" in out and "limit check: OK" in out
    # Slowed by 0.444288 / 0.05 = 8.88576: 20 s become 177.7 s.
    assert "duration 177.715" in out


def test_a_plan_within_its_limits_still_exits_0(capsys):
    status, out, err = run(capsys, "twist", "10", "0.1", "10", "15")
    assert (status, err) == (0, "")
    assert "limit check: OK" in out


def test_the_help_says_what_vmax_does_without_fit(capsys):
    with pytest.raises(SystemExit):
        main(["mobile", "figure8", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "the plan is checked against it (exit 1 when broken)" in text
    assert "--fit slows the curve down to meet it" in text


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["figure8", "--width", "1e12"], "width 1e+12 m and height 1 m"),
        (["figure8", "--width", "1e200"], "width 1e+200 m and height 1 m"),
        (["figure8", "--width", "1e200", "--height", "1e200"], "moves too fast"),
        (["figure8", "--period", "1e-300"], "moves too fast"),
        (["twist", "10", "0.1", "10", "1e12", "--csv", "x.csv"],
         "the distance v * duration is 1e+11 m (v=0.1 m/s, omega=0.174533 rad/s"),
        (["twist", "1e308", "0.1", "10", "10"], "commands; at most 1e+08"),
    ],
)  # fmt: skip
def test_extreme_numbers_are_one_line_errors(argv, message, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    status, out, err = run(capsys, *argv)
    assert status == 2, err
    assert out == ""
    assert err.startswith("trajkit: error: ") and err.count("\n") == 1
    assert message in err
    assert list(tmp_path.iterdir()) == []
