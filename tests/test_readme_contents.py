"""The README's contents list matches its headings: every section and subsection (levels 2-4,
outside code blocks, the set-up section excepted, which stands first) is listed once, in order,
each linked by the anchor GitHub gives its heading (lower case, punctuation dropped, spaces as
hyphens), so a renamed or added section cannot leave a dead or missing entry."""

from __future__ import annotations

import re
from pathlib import Path

README = Path(__file__).resolve().parents[1] / "README.md"


def _headings(text: str) -> list[tuple[int, str]]:
    inside, found = False, []
    for line in text.split("\n"):
        if line.startswith("```"):
            inside = not inside
        elif not inside and (m := re.match(r"^(#{2,4}) (.*)", line)):
            found.append((len(m.group(1)), m.group(2)))
    return found


def _anchor(title: str) -> str:
    return re.sub(r"[^\w\- ]", "", title.lower()).replace(" ", "-")


def test_the_contents_list_every_heading_in_order_with_its_anchor():
    text = README.read_text(encoding="utf-8")
    headings = [(level, title) for level, title in _headings(text) if not title.startswith(("Set up", "Contents"))]
    block = text.split("## Contents\n", 1)[1].split("\n## ", 1)[0]
    entries = re.findall(r"^( *)- \[(.*)\]\(#(.*)\)$", block, flags=re.M)
    assert [(len(indent) // 2 + 2, anchor) for indent, _, anchor in entries] == \
        [(level, _anchor(title)) for level, title in headings]
    assert [label for _, label, _ in entries] == [title.replace("`", "") for _, title in headings]
    assert _anchor("Adding what the library lacks: `--effects-file`") == "adding-what-the-library-lacks---effects-file"
