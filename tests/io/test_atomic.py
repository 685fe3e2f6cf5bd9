"""Tests of trajkit.io.atomic: files are written completely or not at all."""

from __future__ import annotations

import errno
import os
import stat
import subprocess
import sys
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


# ------------------------------------------------- publishing, stale temporaries, errors


def test_a_rename_failing_midway_restores_every_target(tmp_path, monkeypatch):
    # Three outputs, the second rename fails: the first, already replaced, gets its
    # old content back and the third (new) never appears: old PNG, old CSV, no mix.
    import trajkit.io.atomic as atomic

    csv, png, txt = tmp_path / "m.csv", tmp_path / "m.png", tmp_path / "m.txt"
    csv.write_bytes(b"old csv")
    png.write_bytes(b"old png")
    real_replace = os.replace
    calls: list[str] = []

    def replace(source, destination):
        calls.append(os.fspath(destination))
        if len(calls) == 2:
            raise OSError(errno.ENOSPC, "No space left on device", os.fspath(destination))
        real_replace(source, destination)

    monkeypatch.setattr(atomic.os, "replace", replace)
    with pytest.raises(OSError) as excinfo, staged_files() as stage:
        stage.path(csv).write_bytes(b"new csv")
        stage.path(png).write_bytes(b"new png")
        stage.path(txt).write_bytes(b"new txt")
    monkeypatch.undo()
    assert excinfo.value.errno == errno.ENOSPC
    assert excinfo.value.filename == os.fspath(png)  # the target, not a temporary
    assert csv.read_bytes() == b"old csv"
    assert png.read_bytes() == b"old png"
    assert _names(tmp_path) == ["m.csv", "m.png"]  # no new file, no temporary, no backup


def test_a_failed_publish_removes_the_new_files_it_placed(tmp_path, monkeypatch):
    import trajkit.io.atomic as atomic

    real_replace = os.replace
    calls: list[int] = []

    def replace(source, destination):
        calls.append(1)
        if len(calls) == 2:
            raise KeyboardInterrupt
        real_replace(source, destination)

    monkeypatch.setattr(atomic.os, "replace", replace)
    with pytest.raises(KeyboardInterrupt), staged_files() as stage:
        stage.path(tmp_path / "a.csv").write_bytes(b"a")
        stage.path(tmp_path / "b.png").write_bytes(b"b")
    assert _names(tmp_path) == []


def test_temporaries_carry_the_final_name_and_the_process_id(tmp_path):
    from trajkit.io.atomic import final_name

    with staged_files() as stage:
        temporary = stage.path(tmp_path / "move.csv")
        assert temporary.name.startswith(".trajkit-tmp-")
        assert f"-{os.getpid()}-" in temporary.name
        assert temporary.name.endswith("-move.csv")
        assert final_name(temporary) == "move.csv"
        temporary.write_bytes(b"x")
    assert final_name(tmp_path / "plain.gif") == "plain.gif"


def _stale_name(pid: int, name: str) -> str:
    from trajkit.io.atomic import _HOST

    return f".trajkit-tmp-{_HOST}-{pid}-abcd1234-{name}"


def _dead_pid() -> int:
    child = subprocess.Popen([sys.executable, "-c", "pass"])
    child.wait()
    return child.pid  # reaped: no process has this id now (reuse within a test is unlikely)


def test_the_next_write_removes_temporaries_of_dead_processes_only(tmp_path):
    dead = _dead_pid()
    stale_file = tmp_path / _stale_name(dead, "big.csv")
    stale_file.write_bytes(b"partial")
    stale_folder = tmp_path / _stale_name(dead, "bag")
    stale_folder.mkdir()
    (stale_folder / "data").write_bytes(b"x")
    live = tmp_path / _stale_name(os.getppid(), "other.csv")  # its writer still runs
    live.write_bytes(b"being written")
    foreign = tmp_path / ".trajkit-tmp-0badc0de-1-abcd1234-x.csv"  # another host's
    foreign.write_bytes(b"?")
    atomic_write(tmp_path / "out.txt", lambda h: h.write(b"x"))
    assert _names(tmp_path) == sorted([live.name, foreign.name, "out.txt"])


def test_a_sigkilled_writer_leaves_a_temporary_that_the_next_run_removes(tmp_path):
    script = (
        "import sys, time\n"
        "from trajkit.io import atomic_write\n"
        "def write(handle):\n"
        "    handle.write(b'row,' * 100000)\n"
        "    handle.flush()\n"
        "    print('writing', flush=True)\n"
        "    time.sleep(60)\n"
        f"atomic_write({str(tmp_path / 'samples.csv')!r}, write)\n"
    )
    child = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True)
    try:
        assert child.stdout.readline() == "writing\n"
        left = _names(tmp_path)
        assert len(left) == 1 and left[0].endswith("-samples.csv")
        # While the writer lives, its temporary is left alone.
        with staged_files() as stage:
            stage.path(tmp_path / "first.txt").write_bytes(b"1")
        assert left[0] in _names(tmp_path)
    finally:
        child.kill()
        child.wait()
    import trajkit.io.atomic as atomic

    atomic._swept.clear()  # a new run: this process has already searched the folder
    with staged_files() as stage:
        stage.path(tmp_path / "second.txt").write_bytes(b"2")
    assert _names(tmp_path) == ["first.txt", "second.txt"]


def test_data_and_folder_are_flushed_to_disk_before_and_after_the_rename(tmp_path, monkeypatch):
    import trajkit.io.atomic as atomic

    events: list[str] = []
    real_fsync, real_replace = os.fsync, os.replace

    def fsync(descriptor):
        kind = "folder" if stat.S_ISDIR(os.fstat(descriptor).st_mode) else "file"
        events.append(f"fsync {kind}")
        real_fsync(descriptor)

    def replace(source, destination):
        events.append("rename")
        real_replace(source, destination)

    monkeypatch.setattr(atomic.os, "fsync", fsync)
    monkeypatch.setattr(atomic.os, "replace", replace)
    atomic_write(tmp_path / "a.bin", lambda h: h.write(b"a"))
    assert events == ["fsync file", "rename", "fsync folder"]
    events.clear()
    with staged_files() as stage:
        stage.path(tmp_path / "b.bin").write_bytes(b"b")
        stage.path(tmp_path / "c.bin").write_bytes(b"c")
    assert events == ["fsync file", "fsync file", "rename", "rename", "fsync folder"]


def test_write_errors_name_the_target_not_a_temporary(tmp_path):
    def full(handle):
        raise OSError(errno.ENOSPC, "No space left on device")  # write() names no file

    with pytest.raises(OSError) as excinfo:
        atomic_write(tmp_path / "m.csv", full)
    assert (excinfo.value.errno, excinfo.value.filename) == (errno.ENOSPC, str(tmp_path / "m.csv"))
    with pytest.raises(OSError) as excinfo, staged_files() as stage:
        stage.path(tmp_path / "a.png").write_bytes(b"a")
        atomic_write(stage.path(tmp_path / "b.csv"), full)
    assert (excinfo.value.errno, excinfo.value.filename) == (errno.ENOSPC, str(tmp_path / "b.csv"))
    assert _names(tmp_path) == []


def test_a_file_where_the_folder_should_be_is_named(tmp_path):
    (tmp_path / "afile").write_bytes(b"")
    with pytest.raises(NotADirectoryError) as excinfo, staged_files() as stage:
        stage.path(tmp_path / "afile" / "m.csv")
    assert str(excinfo.value) == (
        f"cannot write {tmp_path / 'afile' / 'm.csv'}: {tmp_path / 'afile'} is a file, not a folder"
    )
