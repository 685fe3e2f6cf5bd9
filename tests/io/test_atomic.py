"""Tests of trajkit.io.atomic: files are written completely or not at all."""

from __future__ import annotations

import os
import stat
from pathlib import Path
from typing import IO

import pytest

from trajkit.io import atomic_write, staged_files


class WriterFailed(Exception):
    """Raised on purpose by a writer under test."""


def _names(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir())


def test_writes_the_content_and_returns_the_path(tmp_path: Path) -> None:
    target = tmp_path / "out.bin"
    result = atomic_write(target, lambda handle: handle.write(b"\x00payload\xff"))
    assert result == target
    assert isinstance(result, Path)
    assert target.read_bytes() == b"\x00payload\xff"
    assert _names(tmp_path) == ["out.bin"]


def test_accepts_a_string_and_a_relative_path(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    assert atomic_write("plain.txt", lambda h: h.write(b"a")) == Path("plain.txt")
    assert (tmp_path / "plain.txt").read_bytes() == b"a"
    assert atomic_write(str(tmp_path / "abs.txt"), lambda h: h.write(b"b")) == tmp_path / "abs.txt"
    assert _names(tmp_path) == ["abs.txt", "plain.txt"]


def test_the_writer_gets_a_binary_handle_that_is_closed_afterwards(tmp_path: Path) -> None:
    seen: list[IO[bytes]] = []

    def write(handle: IO[bytes]) -> None:
        assert handle.writable()
        assert "b" in handle.mode
        handle.write(b"x" * 100_000)
        seen.append(handle)

    atomic_write(tmp_path / "big.bin", write)
    assert seen[0].closed
    assert (tmp_path / "big.bin").stat().st_size == 100_000


def test_replaces_an_existing_file(tmp_path: Path) -> None:
    target = tmp_path / "out.txt"
    target.write_bytes(b"old content, longer than the new one")
    atomic_write(target, lambda h: h.write(b"new"))
    assert target.read_bytes() == b"new"
    assert _names(tmp_path) == ["out.txt"]


def test_readers_see_the_old_file_until_the_writer_finishes(tmp_path: Path) -> None:
    target = tmp_path / "out.txt"
    target.write_bytes(b"old")
    during: list[bytes] = []

    def write(handle: IO[bytes]) -> None:
        handle.write(b"new, half written")
        handle.flush()
        during.append(target.read_bytes())

    atomic_write(target, write)
    assert during == [b"old"]
    assert target.read_bytes() == b"new, half written"


def test_a_failing_writer_leaves_no_file_at_all(tmp_path: Path) -> None:
    target = tmp_path / "out.csv"
    error = WriterFailed("disk on fire")

    def write(handle: IO[bytes]) -> None:
        handle.write(b"partial row,1,2,")
        raise error

    with pytest.raises(WriterFailed) as excinfo:
        atomic_write(target, write)
    assert excinfo.value is error  # the writer's own exception, unchanged
    assert not target.exists()
    assert _names(tmp_path) == []  # no temporary file either


def test_a_failing_writer_leaves_an_existing_target_untouched(tmp_path: Path) -> None:
    target = tmp_path / "out.csv"
    target.write_bytes(b"precious")
    before = target.stat()

    def write(handle: IO[bytes]) -> None:
        handle.write(b"garbage")
        raise WriterFailed

    with pytest.raises(WriterFailed):
        atomic_write(target, write)
    assert target.read_bytes() == b"precious"
    after = target.stat()
    assert (after.st_ino, after.st_mtime_ns) == (before.st_ino, before.st_mtime_ns)
    assert _names(tmp_path) == ["out.csv"]


def test_an_interrupt_also_cleans_up(tmp_path: Path) -> None:
    def write(handle: IO[bytes]) -> None:
        handle.write(b"partial")
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        atomic_write(tmp_path / "out.txt", write)
    assert _names(tmp_path) == []


def test_a_missing_folder_raises_and_creates_nothing(tmp_path: Path) -> None:
    target = tmp_path / "missing" / "out.txt"
    calls: list[int] = []
    with pytest.raises(FileNotFoundError):
        atomic_write(target, lambda h: calls.append(1))
    assert calls == []  # the writer never ran
    assert _names(tmp_path) == []


def test_a_directory_in_the_way_raises_and_cleans_up(tmp_path: Path) -> None:
    target = tmp_path / "taken"
    target.mkdir()
    (target / "inside.txt").write_bytes(b"keep")
    with pytest.raises(OSError):
        atomic_write(target, lambda h: h.write(b"data"))
    assert target.is_dir()
    assert (target / "inside.txt").read_bytes() == b"keep"
    assert _names(tmp_path) == ["taken"]


def test_written_files_get_the_usual_permissions(tmp_path: Path) -> None:
    # tempfile creates 0600 files: atomic_write must not hand that mode on.
    old_umask = os.umask(0o022)
    try:
        fresh = atomic_write(tmp_path / "fresh.txt", lambda h: h.write(b"x"))
        existing = tmp_path / "existing.txt"
        existing.write_bytes(b"old")
        existing.chmod(0o640)
        atomic_write(existing, lambda h: h.write(b"new"))
    finally:
        os.umask(old_umask)
    assert stat.S_IMODE(fresh.stat().st_mode) == 0o644  # 0666 less the umask
    assert stat.S_IMODE(existing.stat().st_mode) == 0o640  # an existing file keeps its mode
    assert existing.read_bytes() == b"new"


# ---------------------------------------------------------------- staged_files


def test_staged_files_appear_together(tmp_path: Path) -> None:
    first, second = tmp_path / "move.csv", tmp_path / "move.png"
    second.write_bytes(b"old picture")
    with staged_files() as stage:
        one = stage.path(first)
        two = stage.path(second)
        assert one.parent == tmp_path and two.parent == tmp_path
        assert one.suffix == ".csv" and two.suffix == ".png"  # tools that sniff the suffix
        one.write_bytes(b"csv")
        two.write_bytes(b"png")
        # Nothing is visible before the block ends.
        assert not first.exists()
        assert second.read_bytes() == b"old picture"
        assert stage.targets == [first, second]
    assert first.read_bytes() == b"csv"
    assert second.read_bytes() == b"png"
    assert _names(tmp_path) == ["move.csv", "move.png"]


def test_staged_files_vanish_when_the_block_fails(tmp_path: Path) -> None:
    kept = tmp_path / "kept.csv"
    kept.write_bytes(b"precious")
    with pytest.raises(WriterFailed), staged_files() as stage:
        stage.path(kept).write_bytes(b"half")
        stage.path(tmp_path / "new.png").write_bytes(b"half")
        raise WriterFailed
    assert kept.read_bytes() == b"precious"
    assert _names(tmp_path) == ["kept.csv"]


def test_staged_files_refuse_a_missing_folder_at_once(tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError, match="does not exist"), staged_files() as stage:
        stage.path(tmp_path / "missing" / "out.csv")
    assert _names(tmp_path) == []


def test_staged_files_get_the_usual_permissions(tmp_path: Path) -> None:
    old_umask = os.umask(0o022)
    try:
        with staged_files() as stage:
            stage.path(tmp_path / "out.csv").write_bytes(b"x")
    finally:
        os.umask(old_umask)
    assert stat.S_IMODE((tmp_path / "out.csv").stat().st_mode) == 0o644


def test_staged_files_failing_commit_leaves_no_temporaries_and_no_partial_group(
    tmp_path: Path,
) -> None:
    first = tmp_path / "a.csv"
    first.write_bytes(b"old")
    (tmp_path / "b.png").mkdir()  # the second rename must fail
    with pytest.raises(OSError), staged_files() as stage:
        stage.path(first).write_bytes(b"new")
        stage.path(tmp_path / "b.png").write_bytes(b"img")
    assert _names(tmp_path) == ["a.csv", "b.png"]  # no temporary left behind
    assert first.read_bytes() == b"old"  # all or nothing


def test_staged_folders_appear_with_the_files_or_not_at_all(tmp_path):
    from trajkit.io.atomic import staged_files

    with staged_files() as stage:
        (stage.path(tmp_path / "a.txt")).write_text("a")
        made = stage.folder(tmp_path / "bag")
        made.mkdir()
        (made / "data").write_text("new")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.txt", "bag"]
    assert (tmp_path / "bag" / "data").read_text() == "new"
    # A failure after staging leaves the old folder and file untouched, and no temporaries.
    try:
        with staged_files() as stage:
            stage.path(tmp_path / "a.txt").write_text("b")
            made = stage.folder(tmp_path / "bag")
            made.mkdir()
            (made / "data").write_text("newer")
            raise KeyboardInterrupt
    except KeyboardInterrupt:
        pass
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.txt", "bag"]
    assert (tmp_path / "a.txt").read_text() == "a"
    assert (tmp_path / "bag" / "data").read_text() == "new"
    # Replacing a folder swaps it whole.
    with staged_files() as stage:
        made = stage.folder(tmp_path / "bag")
        made.mkdir()
        (made / "other").write_text("x")
    assert sorted(p.name for p in (tmp_path / "bag").iterdir()) == ["other"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.txt", "bag"]
