"""A sweep's pool workers end with it: killed (SIGKILL) or interrupted (Ctrl-C).

Each test starts ``trajkit sweep`` with two workers in a process of its own, waits
for the workers, and then kills or interrupts it. The workers are found in
``/proc`` (Linux): the children of the sweep's process with its command line (a
forked worker keeps it).
"""

from __future__ import annotations

import os
import select
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

pytestmark = pytest.mark.skipif(
    not sys.platform.startswith("linux") or not Path("/proc/self/stat").exists(),
    reason="finds processes through Linux's /proc",
)

#: A sweep far longer than any test waits: small chunks of time-optimal paths.
SLOW = """\
[sweep]
name = "slow"
planner = "topp"
problems = 200000
chunk = 40
points = 5
grid = 200

[robot]
joints = 3

[fixed]
vmax = 1.0
amax = 2.0

[swept]
waypoints = { uniform = [-1.0, 1.0] }
"""

GONE_WITHIN = 5.0  # s after the sweep's process ends: the workers must be gone by then
START_WITHIN = 60.0  # s for the workers to start and plan a first chunk on a busy machine
# s for an interrupted sweep to end on a busy machine (over 30 s once, on two cores
# running a second test suite beside it).
END_WITHIN = 120.0


def _stat(pid: int) -> tuple[str, int] | None:
    """State letter and parent of ``pid``, or None when it no longer exists."""
    try:
        text = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    fields = text[text.rindex(")") + 2 :].split()  # the name may hold spaces and ')'
    return fields[0], int(fields[1])


def _cmdline(pid: int) -> bytes | None:
    try:
        return Path(f"/proc/{pid}/cmdline").read_bytes()
    except OSError:
        return None


def _workers(parent: int) -> list[int]:
    """The forked children of ``parent`` (same command line): its pool workers."""
    own = _cmdline(parent)
    found = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        stat = _stat(int(entry.name))
        if stat is not None and stat[1] == parent and _cmdline(int(entry.name)) == own:
            found.append(int(entry.name))
    return found


def _alive(pid: int) -> bool:
    stat = _stat(pid)
    return stat is not None and stat[0] not in ("Z", "X")  # a zombie has ended


def _start(tmp_path: Path, *, chunk_done: bool = True, **popen: object
           ) -> tuple[subprocess.Popen, list[int], Path]:  # fmt: skip
    """``trajkit sweep`` of :data:`SLOW` with two workers, once both run (and a chunk is done)."""
    path = tmp_path / "slow.toml"
    path.write_text(SLOW, encoding="utf-8")
    out = tmp_path / "out"
    command = [sys.executable, "-c", "import sys; from trajkit.cli import main; "
               "sys.exit(main())", "sweep", str(path), "--out", str(out), "--workers", "2",
               "--quiet"]  # fmt: skip
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, **popen)
    deadline = time.monotonic() + START_WITHIN
    workers: list[int] = []
    while time.monotonic() < deadline and process.poll() is None:
        workers = _workers(process.pid)
        if len(workers) == 2 and (not chunk_done or any((out / "data").glob("part-*.parquet"))):
            return process, workers, out
        time.sleep(0.05)
    process.kill()
    process.communicate()
    pytest.fail(f"the sweep did not get going: workers {workers}, status {process.returncode}")


def _kill_leftovers(workers: list[int]) -> None:
    for pid in workers:  # only the workers this test started
        if _alive(pid):
            os.kill(pid, signal.SIGKILL)


def _wait_gone(workers: list[int]) -> list[int]:
    deadline = time.monotonic() + GONE_WITHIN
    while time.monotonic() < deadline:
        alive = [pid for pid in workers if _alive(pid)]
        if not alive:
            return []
        time.sleep(0.05)
    return [pid for pid in workers if _alive(pid)]


def test_workers_die_with_a_killed_sweep_and_release_its_output(tmp_path):
    process, workers, _ = _start(tmp_path, chunk_done=False)
    try:
        os.kill(process.pid, signal.SIGKILL)
        process.wait()
        # The workers held the sweep's stdout: `trajkit sweep ... | tee log` never ended.
        readable, _, _ = select.select([process.stdout], [], [], GONE_WITHIN)
        assert readable, f"stdout still open {GONE_WITHIN} s after the kill"
        assert process.stdout.read() == b""
        assert _wait_gone(workers) == []
    finally:
        _kill_leftovers(workers)
        process.stdout.close()
        process.stderr.close()


def test_ctrl_c_ends_the_workers_and_prints_one_line(tmp_path):
    # Ctrl-C signals the terminal's whole process group, the workers too.
    # A terminal's shell starts the sweep with SIGINT at its default; a test runner's
    # worker may ignore SIGINT, which its children would inherit (Python then keeps
    # it ignored).
    process, workers, out = _start(
        tmp_path,
        start_new_session=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    try:
        os.killpg(process.pid, signal.SIGINT)
        stdout, stderr = process.communicate(timeout=END_WITHIN)
        assert process.returncode == 130
        assert stdout == b""
        lines = stderr.decode().splitlines()
        assert len(lines) == 1 and lines[0].startswith("trajkit: interrupted; the finished "
                                                       "chunks are kept"), stderr  # fmt: skip
        assert _wait_gone(workers) == []
        # Every chunk written is whole, and only part files are left in data/.
        names = sorted(path.name for path in (out / "data").iterdir())
        assert names and all(n.startswith("part-") and n.endswith(".parquet") for n in names)
    finally:
        _kill_leftovers(workers)
        if process.poll() is None:
            process.kill()
            process.communicate()
