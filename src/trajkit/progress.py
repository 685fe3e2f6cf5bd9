"""One progress bar for every long job (sweeps, animations): a line that fills up.

On a terminal the line is redrawn in place; elsewhere (a log, a pipe) it is
written anew each time the bar fills one more twentieth, so a log gets about
twenty lines, not one per step.
"""

from __future__ import annotations

from typing import TextIO

__all__ = ["ProgressBar"]

WIDTH = 20  # characters of the bar


class ProgressBar:
    """``[#####...............] detail`` for ``done`` of ``total`` steps.

    Parameters
    ----------
    total : int
        Steps of the job (> 0).
    label : str
        Text before the bar (e.g. the file being written).
    stream : text stream or None
        Where to draw; None draws nothing.
    live : bool, optional
        Redraw in place (carriage return); default: whether ``stream`` is a terminal.

    Notes
    -----
    Call the bar with the steps done and a detail (counts, rates, a percentage);
    :meth:`close` ends a line left open, so that a message after an interruption
    starts on a line of its own.
    """

    def __init__(
        self, total: int, label: str = "", stream: TextIO | None = None, *, live: bool | None = None
    ) -> None:
        self.total = max(int(total), 1)
        self.label = f"{label} " if label else ""
        self.stream = stream
        isatty = getattr(stream, "isatty", None)
        self.live = bool(isatty()) if live is None and isatty is not None else bool(live)
        self._shown = ""  # the line last drawn
        self._filled = -1
        self._open = False  # a live line without its newline yet

    def __call__(self, done: int, detail: str = "") -> None:
        """Show ``done`` steps of the total, with ``detail`` after the bar."""
        if self.stream is None:
            return
        filled = min(WIDTH, WIDTH * done // self.total)  # full only when done
        finished = done >= self.total
        line = f"{self.label}[{'#' * filled}{'.' * (WIDTH - filled)}] {detail}".rstrip()
        if self.live:
            if line == self._shown and not finished:
                return
            self.stream.write("\r" + line + ("\n" if finished else ""))
            self._open = not finished
        elif filled != self._filled or finished:
            self.stream.write(line + "\n")
        else:
            return
        self.stream.flush()
        self._shown, self._filled = line, filled

    def close(self) -> None:
        """End the bar's line if it is still open (an interrupted or failed job)."""
        if self._open and self.stream is not None:
            self.stream.write("\n")
            self.stream.flush()
            self._open = False
