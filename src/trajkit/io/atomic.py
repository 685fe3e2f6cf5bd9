"""Write a file completely or not at all; write a group of files all together or not at all.

Temporaries are named ``.trajkit-tmp-<host>-<pid>-<random>-<final name>`` beside
their destination. A process killed outright (SIGKILL, a power loss) cannot
remove its own; the next trajkit process that writes into the same folder finds
those whose owner is no longer running on this host and removes them. Data are
flushed to the disk (``fsync``) before a temporary is renamed onto its target,
and the folder after, so after a crash a target holds either its old content or
the whole new one, never an empty or truncated file.
"""

from __future__ import annotations

import contextlib
import errno
import hashlib
import os
import re
import shutil
import socket
import tempfile
import threading
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import IO

__all__ = [
    "StagedFiles",
    "atomic_path",
    "atomic_write",
    "final_name",
    "staged_files",
    "temporary_path",
]

TEMP_PREFIX = ".trajkit-tmp-"
# A host tag keeps a process from judging, by pid, temporaries that another machine
# is writing into a shared (network) folder.
_HOST = hashlib.sha1(socket.gethostname().encode("utf-8", "replace")).hexdigest()[:8]
_TEMP_NAME = re.compile(r"^\.trajkit-tmp-([0-9a-f]{8})-(\d+)-([a-z0-9_]+)-(.+)$")
# Errors of writing data whose exception names no file (``write()`` and ``fsync()``).
_WRITE_ERRNOS = frozenset(
    code
    for code in (errno.ENOSPC, errno.EIO, getattr(errno, "EDQUOT", None), errno.EFBIG, errno.EROFS)
    if code is not None
)

_lock = threading.Lock()
_swept: set[str] = set()  # folders already searched for stale temporaries by this process
_destinations: dict[str, Path] = {}  # temporary path -> final path, while it exists


def temporary_path(target: str | os.PathLike[str], *, folder: bool = False) -> Path:
    """Create an empty temporary file (or folder) beside ``target`` and return its path.

    The name ends with ``target``'s name (so tools that read the suffix still
    work) and carries this process's id, so that a later run can remove it if
    this process is killed before it could. Stale temporaries of dead processes
    in the same folder are removed first.

    Raises
    ------
    FileNotFoundError
        If ``target``'s folder does not exist.
    NotADirectoryError
        If what should be ``target``'s folder is a file.
    """
    destination = Path(target)
    parent = destination.parent if str(destination.parent) else Path(".")
    if not parent.is_dir():
        if parent.exists() or any(p.is_file() for p in parent.parents):
            raise NotADirectoryError(
                f"cannot write {destination}: {_first_file(parent)} is a file, not a folder"
            )
        raise FileNotFoundError(f"folder {parent} does not exist (for {destination.name})")
    remove_stale_temporaries(parent)
    prefix = f"{TEMP_PREFIX}{_HOST}-{os.getpid()}-"
    # Long names are cut from the front: the suffix, which writers look at, is kept.
    suffix = "-" + destination.name[-(200 - len(prefix)) :]
    try:
        if folder:
            name = tempfile.mkdtemp(dir=parent, prefix=prefix, suffix=suffix)
        else:
            descriptor, name = tempfile.mkstemp(dir=parent, prefix=prefix, suffix=suffix)
            os.close(descriptor)
    except OSError as exc:
        raise _naming(exc, destination) from exc
    with _lock:
        _destinations[name] = destination
    return Path(name)


def _first_file(folder: Path) -> Path:
    """The part of ``folder``'s path that is a file (why it cannot be a folder)."""
    for candidate in (*reversed(folder.parents), folder):
        if candidate.exists() and not candidate.is_dir():
            return candidate
    return folder


def final_name(path: str | os.PathLike[str]) -> str:
    """The name a temporary from :func:`temporary_path` will be published under.

    For any other path, its own name. Progress messages show this, not the
    temporary's name.
    """
    key = os.fspath(path)
    for _ in range(8):  # a temporary of a temporary (a file written atomically, staged)
        with _lock:
            known = _destinations.get(key)
        if known is None:
            break
        key = os.fspath(known)
    name = Path(key).name
    while (match := _TEMP_NAME.match(name)) is not None:
        name = match.group(4)
    return name


def _forget(path: str | os.PathLike[str]) -> None:
    with _lock:
        _destinations.pop(os.fspath(path), None)


def _is_temporary(name: str | os.PathLike[str] | None) -> bool:
    return name is not None and _TEMP_NAME.match(Path(os.fsdecode(name)).name) is not None


def _alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    if os.name != "posix":  # no cheap liveness test: never remove what might be in use
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # EPERM: alive, owned by someone else
        return True
    return True


def remove_stale_temporaries(folder: str | os.PathLike[str]) -> list[Path]:
    """Remove the temporaries in ``folder`` left by trajkit processes that have died.

    Only names made by :func:`temporary_path` on this host are considered, and
    only those whose owning process is no longer running. Each folder is searched
    once per process. Returns what was removed.
    """
    where = Path(folder)
    key = os.path.abspath(where)
    with _lock:
        if key in _swept:
            return []
        _swept.add(key)
    removed: list[Path] = []
    try:
        entries = list(os.scandir(where))
    except OSError:
        return removed
    for entry in entries:
        match = _TEMP_NAME.match(entry.name)
        if match is None or match.group(1) != _HOST or _alive(int(match.group(2))):
            continue
        path = Path(entry.path)
        with contextlib.suppress(OSError):
            if entry.is_dir(follow_symlinks=False):
                shutil.rmtree(path)
            else:
                path.unlink()
            removed.append(path)
    return removed


def _naming(exc: OSError, target: Path) -> OSError:
    """``exc`` as it should read: about ``target``, not a temporary or no file at all."""
    if exc.errno is None or exc.strerror is None:
        return exc
    if exc.filename is not None and not _is_temporary(exc.filename):
        return exc
    try:
        renamed = type(exc)(exc.errno, exc.strerror, os.fspath(target))
    except Exception:  # an OSError subclass with its own constructor: leave it
        return exc
    return renamed


def _fsync_file(path: Path) -> None:
    descriptor = os.open(path, os.O_RDONLY)
    try:
        os.fsync(descriptor)
    finally:
        os.close(descriptor)


def _fsync_folder(folder: Path) -> None:
    """Make renames in ``folder`` durable; a file system that cannot is left alone."""
    if os.name != "posix":
        return
    try:
        descriptor = os.open(folder, os.O_RDONLY | getattr(os, "O_DIRECTORY", 0))
    except OSError:
        return
    try:
        os.fsync(descriptor)
    except OSError:  # EINVAL: this file system does not sync folders
        pass
    finally:
        os.close(descriptor)


def _folder_of(path: Path) -> Path:
    return path.parent if str(path.parent) else Path(".")


def atomic_write(path: str | os.PathLike[str], write: Callable[[IO[bytes]], None]) -> Path:
    """Call ``write(handle)`` on a temporary file beside ``path``, then rename it.

    A reader never sees a half-written file, and a failure (an exception in
    ``write``, a full disk) leaves no file behind: the temporary is removed. The
    data reach the disk before the rename, so a crash leaves the old file or
    the whole new one.

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

    Raises
    ------
    OSError
        If the file cannot be written; its ``filename`` is ``path`` (not the
        temporary), e.g. ``OSError(ENOSPC)`` on a full disk.
    """
    with atomic_path(path) as temporary, open(temporary, "wb") as handle:
        write(handle)
    return Path(path)


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike[str]) -> Iterator[Path]:
    """A temporary path beside ``path`` to write to; renamed onto ``path`` on success.

    For writers that take a file name rather than a handle (matplotlib's animation
    writers): the same guarantees as :func:`atomic_write`, which is built on it. The
    file is flushed to disk and given the mode ``open()`` would give it before the
    rename, and the folder after it; on any exception the temporary is removed and an
    ``OSError`` names ``path``.
    """
    target = Path(path)
    temporary = temporary_path(target)
    try:
        yield temporary
        _fsync_file(temporary)
        os.chmod(temporary, _mode_for(target))
        os.replace(temporary, target)
    except BaseException as exc:
        with contextlib.suppress(OSError):
            os.unlink(temporary)
        _forget(temporary)
        if isinstance(exc, OSError):
            renamed = _naming(exc, target)
            if renamed is not exc:
                raise renamed from exc
        raise
    _forget(temporary)
    _fsync_folder(_folder_of(target))


def _mode_for(target: Path) -> int:
    """Permissions the file would have had if opened normally.

    An existing file keeps its mode; a new one gets ``0o666`` less the umask
    (tempfile creates files as 0600).
    """
    try:
        return target.stat().st_mode & 0o7777
    except FileNotFoundError:
        return new_file_mode()


def new_file_mode() -> int:
    """``0o666`` less the process's umask: the mode ``open()`` gives a new file."""
    with _lock:  # the umask can only be read by setting it
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

        Raises ``FileNotFoundError`` at once when the target's folder does not
        exist, ``NotADirectoryError`` when it is a file.
        """
        destination = Path(target)
        temporary = temporary_path(destination)
        self._pending.append((temporary, destination))
        self.sources[destination] = temporary
        return temporary

    def folder(self, target: str | os.PathLike[str]) -> Path:
        """A path for a whole folder to appear at ``target`` with the files; create it there.

        The path lies in a temporary folder beside ``target`` and does not exist yet.
        """
        destination = Path(target)
        scratch = temporary_path(destination, folder=True)
        path = scratch / destination.name
        self._folders.append((scratch, path, destination))
        self.sources[destination] = path
        return path

    @property
    def targets(self) -> list[Path]:
        """Final paths, in the order they were staged (files, then folders)."""
        return [target for _, target in self._pending] + [t for _, _, t in self._folders]

    def _target_of(self, exc: OSError) -> Path | None:
        """The output an error while writing the staged files is about."""
        name = None if exc.filename is None else os.fsdecode(exc.filename)
        for temporary, target in self._pending:
            if name is not None and name == os.fspath(temporary):
                return target
        for scratch, _, target in self._folders:
            if name is not None and name.startswith(os.fspath(scratch)):
                return target
        if name is None and exc.errno in _WRITE_ERRNOS and self._pending:
            return self._pending[-1][1]  # write() errors name no file: the latest one
        return None

    def _discard(self) -> None:
        for temporary, _ in self._pending:
            with contextlib.suppress(OSError):
                os.unlink(temporary)
            _forget(temporary)
        self._discard_folders()

    def _discard_folders(self) -> None:
        for scratch, _, _ in self._folders:
            shutil.rmtree(scratch, ignore_errors=True)
            _forget(scratch)


@contextlib.contextmanager
def staged_files() -> Iterator[StagedFiles]:
    """Write several files so that either all of them appear or none does.

    Examples
    --------
    >>> with staged_files() as stage:  # doctest: +SKIP
    ...     samples.to_csv(stage.path("move.csv"))
    ...     plot.save(figure, stage.path("move.png"))

    If the block raises, every temporary file is removed and no target changes;
    otherwise each temporary is flushed to disk and renamed onto its target. If
    a rename fails midway (a full disk, a permission), the targets already
    replaced get their old content back and new ones are removed, so the group
    is never left half old, half new.

    Raises
    ------
    OSError
        Naming the target (not the temporary) that could not be written.
    """
    stage = StagedFiles()
    try:
        yield stage
    except BaseException as exc:
        stage._discard()
        if isinstance(exc, OSError):
            target = stage._target_of(exc)
            if target is not None:
                renamed = _naming(exc, target)
                if renamed is not exc:
                    raise renamed from exc
        raise
    try:
        _publish(stage)
    except OSError as exc:
        target = stage._target_of(exc)
        renamed = exc if target is None else _naming(exc, target)
        if renamed is not exc:
            raise renamed from exc
        raise
    finally:
        stage._discard()


def _publish(stage: StagedFiles) -> None:
    """Rename every staged output onto its target, or on failure restore them all."""
    for _, target in stage._pending:
        if target.is_dir():
            raise IsADirectoryError(errno.EISDIR, "it is a folder", os.fspath(target))
    for _, made, target in stage._folders:
        if not made.is_dir():
            raise FileNotFoundError(f"the folder for {target} was not written")
        if target.exists() and not target.is_dir():
            raise NotADirectoryError(f"cannot replace {target} with a folder: it is a file")
    folders: set[Path] = set()
    for temporary, target in stage._pending:
        try:
            _fsync_file(temporary)
        except OSError as exc:
            raise _naming(exc, target) from exc
        os.chmod(temporary, _mode_for(target))
        folders.add(_folder_of(target))
    # (target, backup or None for a new file, kind) of every output already placed
    placed: list[tuple[Path, Path | None, bool]] = []
    try:
        for temporary, target in stage._pending:
            backup = _backup(target) if target.exists() else None
            try:
                os.replace(temporary, target)
            except BaseException:
                if backup is not None:
                    _remove(backup)
                raise
            placed.append((target, backup, False))
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
            placed.append((target, old if old.exists() else None, True))
            folders.add(_folder_of(target))
    except BaseException:
        _roll_back(placed, stage)
        raise
    for _, backup, is_folder in placed:
        if backup is not None and not is_folder:
            _remove(backup)
    for folder in folders:
        _fsync_folder(folder)


def _backup(target: Path) -> Path:
    """A second name for ``target``'s current content, to put back if publishing fails."""
    backup = temporary_path(target)
    os.unlink(backup)
    try:
        os.link(target, backup)  # instant, and the target never goes missing
    except OSError:  # no hard links here (FAT, some network shares): copy
        shutil.copy2(target, backup)
    return backup


def _remove(path: Path) -> None:
    with contextlib.suppress(OSError):
        os.unlink(path)
    _forget(path)


def _roll_back(placed: list[tuple[Path, Path | None, bool]], stage: StagedFiles) -> None:
    """Undo the renames of a failed publish, newest first; best effort, never raises."""
    scratch_of = {target: scratch for scratch, _, target in stage._folders}
    for target, backup, is_folder in reversed(placed):
        with contextlib.suppress(OSError):
            if is_folder:
                # The new folder goes back into its scratch folder, to be discarded.
                os.replace(target, scratch_of[target] / (target.name + ".new"))
                if backup is not None:
                    os.replace(backup, target)
            elif backup is not None:
                os.replace(backup, target)
                _forget(backup)
            else:
                os.unlink(target)
