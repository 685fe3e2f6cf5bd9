"""The HTML report: self-contained, escaped, atomic; rendered in headless Chromium."""

from __future__ import annotations

import base64
import os
import re
import shutil
import subprocess
from pathlib import Path

import pytest

from trajkit import scenario
from trajkit.viz.report import Entry, write_report

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
#: The flags a closed-network machine needs (no background connections, no sandbox as root).
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--virtual-time-budget=5000"]  # fmt: skip
PIXEL = base64.b64decode(  # a 1x1 PNG
    "iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mNk+M9QDwADhgGAWjR9awAAAABJRU5ErkJggg=="
)


def entry(tmp_path: Path, name: str = "move", pictures: int = 1, broken: bool = False) -> Entry:
    files = []
    for index in range(pictures):
        path = tmp_path / f"{name}_{index}.png"
        path.write_bytes(b"not a png" if broken else PIXEL)
        files.append(path)
    (tmp_path / f"{name}.csv").write_text("t\n0\n", encoding="utf-8")
    files.append(tmp_path / f"{name}.csv")
    return Entry(name, "a <b>bold</b> move", 1.5, True, "velocity 1 deg/s", "max error 0.1 deg",
                 ["line 1", "line 2"], files, 'name = "move"\n')  # fmt: skip


def test_report_is_self_contained_and_escaped(tmp_path):
    path = write_report(tmp_path / "index.html", [entry(tmp_path)], title="a <test>",
                        intro="see <here>")  # fmt: skip
    page = path.read_text(encoding="utf-8")
    assert page.startswith("<!DOCTYPE html>")
    assert "<title>a &lt;test&gt;</title>" in page and "see &lt;here&gt;" in page
    assert "a &lt;b&gt;bold&lt;/b&gt; move" in page and "<b>bold</b>" not in page
    assert page.count("data:image/png;base64,") == 1
    assert '<li><a href="move.csv">move.csv</a></li>' in page  # other files are linked
    assert "name = &quot;move&quot;" in page  # the scenario echoed, escaped
    assert 'src="http' not in page and 'href="http' not in page  # nothing fetched
    assert sorted(os.listdir(tmp_path)) == ["index.html", "move.csv", "move_0.png"]


def test_a_scenario_run_reports_its_figures(tmp_path):
    path = scenario.EXAMPLES / "seed001_six_joint_trapezoid.toml"
    spec = scenario.load(path)
    outcome = scenario.execute(spec, tmp_path, log=len)
    report = scenario.report_entry(spec, outcome)
    assert report.name == spec.name and report.ok and report.duration == pytest.approx(14.608)
    assert report.limits == ("velocity 7, 7, 7, 3.5, 3.5, 3.5 deg/s; acceleration 4, 4, 4, 2, 2, "
                             "2 deg/s²")  # fmt: skip
    assert report.scenario == path.read_text(encoding="utf-8")


def chromium(*arguments: str, tmp_path: Path) -> str:
    result = subprocess.run(
        [CHROMIUM, *FLAGS, f"--user-data-dir={tmp_path / 'profile'}", *arguments],
        capture_output=True, text=True, timeout=120,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr[-2000:]
    return result.stdout


@pytest.mark.skipif(CHROMIUM is None, reason="Chromium is not installed (Debian: apt install "
                    "chromium); .ci/run installs it")  # fmt: skip
def test_report_renders_in_chromium_with_every_picture_loaded(tmp_path):
    files = [scenario.EXAMPLES / "seed000_jackal_twist.toml",
             scenario.EXAMPLES / "seed002_two_link_ellipse.toml"]  # fmt: skip
    entries = []
    for path in files:
        spec = scenario.load(path)
        entries.append(scenario.report_entry(spec, scenario.execute(spec, tmp_path, log=len)))
    page = write_report(tmp_path / "index.html", entries)
    dom = chromium("--dump-dom", page.as_uri(), tmp_path=tmp_path)
    images = int(re.search(r'data-images="(\d+)"', dom).group(1))
    # twist: time panels and path; ellipse: joints, task space and its animation (a GIF)
    assert images == 5
    assert 'data-broken="0"' in dom
    shot = tmp_path / "shot.png"
    chromium("--window-size=1200,900", f"--screenshot={shot}", page.as_uri(), tmp_path=tmp_path)
    from PIL import Image

    with Image.open(shot) as image:
        assert image.size == (1200, 900)
        colours = image.convert("RGB").getcolors(maxcolors=1_000_000)
        assert colours is not None and len(colours) > 50  # text and plots, not a blank page


@pytest.mark.skipif(CHROMIUM is None, reason="Chromium is not installed")
def test_a_broken_picture_is_flagged_on_the_page(tmp_path):
    page = write_report(tmp_path / "index.html", [entry(tmp_path, broken=True)])
    dom = chromium("--dump-dom", page.as_uri(), tmp_path=tmp_path)
    assert 'data-broken="1"' in dom
    assert "Pictures that did not load: move_0.png" in dom
