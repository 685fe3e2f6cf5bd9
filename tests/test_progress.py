"""The one progress bar: redrawn on a terminal, a line per twentieth elsewhere."""

from __future__ import annotations

import io

from trajkit.progress import ProgressBar


def _stream(tty: bool) -> io.StringIO:
    stream = io.StringIO()
    stream.isatty = lambda: tty  # type: ignore[method-assign]
    return stream


def test_on_a_terminal_the_line_is_redrawn_and_ended_once() -> None:
    stream = _stream(True)
    bar = ProgressBar(4, "job", stream)
    for done in range(1, 5):
        bar(done, f"{done}/4")
    assert stream.getvalue() == (
        "\rjob [#####...............] 1/4\rjob [##########..........] 2/4"
        "\rjob [###############.....] 3/4\rjob [####################] 4/4\n"
    )
    bar.close()  # nothing left open
    assert stream.getvalue().count("\n") == 1


def test_an_unchanged_line_is_not_redrawn_and_close_ends_an_open_one() -> None:
    stream = _stream(True)
    bar = ProgressBar(1000, stream=stream)
    for done in range(10):
        bar(done)
    assert stream.getvalue().count("\r") == 1  # the bar has not moved
    bar.close()
    bar.close()
    assert stream.getvalue() == "\r[....................]\n"


def test_off_a_terminal_about_twenty_lines_are_written() -> None:
    stream = _stream(False)
    bar = ProgressBar(1000, "sweep", stream)
    for done in range(1, 1001):
        bar(done, f"{done} problems")
    lines = stream.getvalue().splitlines()
    assert len(lines) == 21 and "\r" not in stream.getvalue()  # the empty bar, then 20
    assert lines[-1] == "sweep [####################] 1000 problems"
    bar.close()
    assert len(stream.getvalue().splitlines()) == 21


def test_without_a_stream_nothing_is_drawn() -> None:
    bar = ProgressBar(3, "quiet", None)
    bar(1, "x")
    bar.close()  # no stream, no error
