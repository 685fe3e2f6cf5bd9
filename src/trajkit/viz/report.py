"""A self-contained HTML report of scenario runs: summary table, pictures, the scenarios.

One ``index.html`` holds everything: plots and animations are embedded as data
URIs, so the page can be mailed or archived alone. A small script marks every
picture that failed to load (a banner names them), which is also what the test
suite checks in a headless browser.
"""

from __future__ import annotations

import base64
import html
import os
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

from trajkit.io.atomic import atomic_write

__all__ = ["Entry", "page_title", "write_report"]

_PICTURES = {".png": "image/png", ".gif": "image/gif", ".svg": "image/svg+xml",
             ".mp4": "video/mp4"}  # fmt: skip
_STYLE = """
body { font: 15px/1.45 system-ui, sans-serif; margin: 2em auto; max-width: 1100px;
       color: #1d2330; padding: 0 1em; }
h1 { font-size: 1.6em; } h2 { font-size: 1.25em; margin-top: 2.2em;
     border-bottom: 1px solid #d6dbe3; }
table { border-collapse: collapse; width: 100%; margin: 1em 0; }
th, td { text-align: left; padding: .35em .6em; border-bottom: 1px solid #e4e8ee; }
th { background: #f3f5f8; } td.ok { color: #1a7f37; } td.failed { color: #b42318; }
figure { display: inline-block; margin: .5em; vertical-align: top; }
figure img { max-width: 520px; border: 1px solid #e4e8ee; }
figcaption { font-size: .85em; color: #5b6473; }
pre { background: #f6f8fa; padding: .8em; overflow-x: auto; font-size: .85em; }
#broken { display: none; background: #fde8e8; color: #b42318; padding: .6em; }
"""
_CHECK = """
window.addEventListener("load", () => {
  const images = [...document.images];
  const broken = images.filter((img) => !(img.complete && img.naturalWidth > 0));
  document.documentElement.dataset.images = images.length;
  document.documentElement.dataset.broken = broken.length;
  if (broken.length) {
    const banner = document.getElementById("broken");
    banner.textContent = "Pictures that did not load: " + broken.map((i) => i.alt).join(", ");
    banner.style.display = "block";
  }
});
"""


@dataclass(frozen=True)
class Entry:
    """One scenario run in the report.

    Attributes
    ----------
    name, description : str
    duration : float
        The plan's duration (s).
    ok : bool
        Whether the plan kept every limit.
    limits : str
        The limits the plan was checked against, in words.
    tracking : str
        A line about the simulated tracking, or ``""``.
    lines : sequence of str
        The run's summary.
    files : sequence of Path
        What it wrote; pictures among them are shown, the rest listed.
    scenario : str
        The scenario file's text, echoed.
    """

    name: str
    description: str
    duration: float
    ok: bool
    limits: str
    tracking: str
    lines: Sequence[str]
    files: Sequence[Path]
    scenario: str


def _picture(path: Path, source: Path) -> str:
    kind = _PICTURES[path.suffix.lower()]
    data = base64.b64encode(source.read_bytes()).decode("ascii")
    if kind.startswith("video/"):
        return (f'<figure><video controls loop muted src="data:{kind};base64,{data}"></video>'
                f"<figcaption>{html.escape(path.name)}</figcaption></figure>")  # fmt: skip
    name = html.escape(path.name)
    return (f'<figure><img src="data:{kind};base64,{data}" alt="{name}">'
            f"<figcaption>{name}</figcaption></figure>")  # fmt: skip


def _relative(target: Path, folder: Path) -> str:
    try:
        return Path(os.path.relpath(target, folder)).as_posix()
    except ValueError:  # another drive
        return target.as_uri()


def page_title(path: str | os.PathLike[str]) -> str | None:
    """The title of the page at ``path``: None if no file is there, "" if it has none.

    Lets a command tell its own earlier page from another one's before replacing it;
    a page without a title is not one of trajkit's, so it is not replaced either.
    """
    try:
        with open(path, "rb") as handle:
            head = handle.read(4096).decode("utf-8", "replace")
    except FileNotFoundError:
        return None
    except OSError:
        return ""  # there, but unreadable: not ours to replace
    match = re.search(r"<title>(.*?)</title>", head, flags=re.DOTALL)
    return "" if match is None else html.unescape(match.group(1))


def write_report(
    path: str | os.PathLike[str],
    entries: Sequence[Entry],
    *,
    title: str = "trajkit report",
    intro: str = "",
    sources: Mapping[Path, Path] | None = None,
) -> Path:
    """Write the report page (atomically) and return its path.

    Parameters
    ----------
    path : path-like
        The ``.html`` file to write; pictures are read from the entries' files.
    entries : sequence of Entry
    title : str
    intro : str
        A paragraph (plain text) under the title.
    sources : mapping, optional
        Where each entry file can be read now, when not at its own path (outputs
        still staged under temporary names).
    """
    sources = {} if sources is None else dict(sources)
    rows = []
    for entry in entries:
        verdict = "ok" if entry.ok else "failed"
        rows.append(
            f'<tr><td><a href="#{html.escape(entry.name)}">{html.escape(entry.name)}</a></td>'
            f"<td>{html.escape(entry.description)}</td><td>{entry.duration:.6g} s</td>"
            f"<td>{html.escape(entry.limits)}</td>"
            f'<td class="{verdict}">{"OK" if entry.ok else "FAILED"}</td>'
            f"<td>{html.escape(entry.tracking)}</td></tr>"
        )
    sections = []
    for entry in entries:
        pictures = [f for f in entry.files
                    if f.suffix.lower() in _PICTURES and sources.get(f, f).is_file()]  # fmt: skip
        others = [f for f in entry.files if f not in pictures]
        folder = Path(path).parent
        listed = "".join(f'<li><a href="{html.escape(_relative(f, folder))}">'
                         f"{html.escape(f.name)}</a></li>" for f in others)  # fmt: skip
        sections.append(
            f'<h2 id="{html.escape(entry.name)}">{html.escape(entry.name)}</h2>'
            f"<p>{html.escape(entry.description)}</p>"
            f"<pre>{html.escape(chr(10).join(entry.lines))}</pre>"
            + "".join(_picture(p, sources.get(p, p)) for p in pictures)
            + (f"<p>Also written:</p><ul>{listed}</ul>" if listed else "")
            + f"<details><summary>Scenario file</summary><pre>{html.escape(entry.scenario)}"
            "</pre></details>"
        )
    page = (
        "<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'>"
        f"<title>{html.escape(title)}</title><style>{_STYLE}</style>"
        f"<script>{_CHECK}</script></head><body>"
        f"<h1>{html.escape(title)}</h1><div id='broken'></div>"
        + (f"<p>{html.escape(intro)}</p>" if intro else "")
        + "<table><tr><th>scenario</th><th>what</th><th>duration</th><th>limits</th>"
        f"<th>check</th><th>tracking</th></tr>{''.join(rows)}</table>{''.join(sections)}</body></html>"
    )
    data = page.encode("utf-8")
    return atomic_write(path, lambda handle: handle.write(data))
