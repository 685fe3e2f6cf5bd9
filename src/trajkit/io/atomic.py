"""Write a file completely or not at all."""

from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import IO

__all__ = ["StagedFiles", "atomic_write", "staged_files"]


def atomic_write(path: str | os.PathLike[str], write: Callable[[IO[bytes]], None]) -> Path:
    """Call ``write(handle)`` on a temporary file beside ``path``, then rename it.

    A reader never sees a half-written file, and a failure (an exception in
    ``write``, a full disk) leaves no file behind: the temporary is removed.

    Parameters
    ----------
    path : path-like
        Destination; its folder must exist.
    write : callable
        Receives a binary file handle and writes the whole content.

    Returns
    -------
    Path
        The destination path.
    """
    target = Path(path)
    folder = target.parent if str(target.parent) else Path(".")
    handle = tempfile.NamedTemporaryFile(
        mode="wb", dir=folder, prefix=f".{target.name}.", suffix=".tmp", delete=False
    )
    try:
        with handle:
            write(handle)
        os.chmod(handle.name, _mode_for(target))
        os.replace(handle.name, target)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(handle.name)
        raise
    return target


def _mode_for(target: Path) -> int:
    """Permissions the file would have had if opened normally.

    An existing file keeps its mode; a new one gets ``0o666`` less the umask
    (tempfile creates files as 0600).
    """
    try:
        return target.stat().st_mode & 0o7777
    except FileNotFoundError:
        mask = os.umask(0)
        os.umask(mask)
        return 0o666 & ~mask


class StagedFiles:
    """Temporary paths for a group of output files that appear together or not at all.

    Use through :func:`staged_files`.
    """

    def __init__(self) -> None:
        self._pending: list[tuple[Path, Path]] = []
        self._folders: list[tuple[Path, Path, Path]] = []
        self.sources: dict[Path, Path] = {}

    def path(self, target: str | os.PathLike[str]) -> Path:
        """A temporary path beside ``target`` with the same suffix; write there.

        Raises ``FileNotFoundError`` at once when the target's folder does not exist.
        """
        destination = Path(target)
        folder = destination.parent if str(destination.parent) else Path(".")
        if not folder.is_dir():
            raise FileNotFoundError(f"folder {folder} does not exist (for {destination.name})")
        descriptor, name = tempfile.mkstemp(
            dir=folder, prefix=f".{destination.stem}.", suffix=f".tmp{destination.suffix}"
        )
        os.close(descriptor)
        temporary = Path(name)
        self._pending.append((temporary, destination))
        self.sources[destination] = temporary
        return temporary

    def folder(self, target: str | os.PathLike[str]) -> Path:
        """A path for a whole folder to appear at ``target`` with the files; create it there.

        The path lies in a temporary folder beside ``target`` and does not exist yet.
        """
        destination = Path(target)
        parent = destination.parent if str(destination.parent) else Path(".")
        if not parent.is_dir():
            raise FileNotFoundError(f"folder {parent} does not exist (for {destination.name})")
        scratch = Path(tempfile.mkdtemp(dir=parent, prefix=f".{destination.name}.", suffix=".tmp"))
        path = scratch / destination.name
        self._folders.append((scratch, path, destination))
        self.sources[destination] = path
        return path

    @property
    def targets(self) -> list[Path]:
        """Final paths, in the order they were staged (files, then folders)."""
        return [target for _, target in self._pending] + [t for _, _, t in self._folders]

    def _discard_folders(self) -> None:
        for scratch, _, _ in self._folders:
            shutil.rmtree(scratch, ignore_errors=True)


@contextlib.contextmanager
def staged_files() -> Iterator[StagedFiles]:
    """Write several files so that either all of them appear or none does.

    Examples
    --------
    >>> with staged_files() as stage:  # doctest: +SKIP
    ...     samples.to_csv(stage.path("move.csv"))
    ...     plot.save(figure, stage.path("move.png"))

    If the block raises, every temporary file is removed and no target changes;
    otherwise each temporary is renamed onto its target.
    """
    stage = StagedFiles()
    try:
        yield stage
    except BaseException:
        for temporary, _ in stage._pending:
            with contextlib.suppress(OSError):
                os.unlink(temporary)
        stage._discard_folders()
        raise
    pending = list(stage._pending)
    try:
        for _, target in pending:
            if target.is_dir():
                raise IsADirectoryError(f"cannot write {target}: it is a folder")
        for _, made, target in stage._folders:
            if not made.is_dir():
                raise FileNotFoundError(f"the folder for {target} was not written")
            if target.exists() and not target.is_dir():
                raise NotADirectoryError(f"cannot replace {target} with a folder: it is a file")
        while pending:
            temporary, target = pending[0]
            os.chmod(temporary, _mode_for(target))
            os.replace(temporary, target)
            pending.pop(0)
        for scratch, made, target in stage._folders:
            old = scratch / (target.name + ".old")
            if target.exists():
                os.replace(target, old)  # swapped out; dropped with the scratch folder
            try:
                os.replace(made, target)
            except BaseException:
                if old.exists():
                    os.replace(old, target)  # the old folder stays where it was
                raise
    except BaseException:
        # A rename failed midway (rare: checked above): remove what was not placed.
        for temporary, _ in pending:
            with contextlib.suppress(OSError):
                os.unlink(temporary)
        raise
    finally:
        stage._discard_folders()
