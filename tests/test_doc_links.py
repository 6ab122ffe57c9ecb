"""Every relative link of the front door (README.md), the docs (docs/*.md) and the other READMEs resolves: its file
is there, and a fragment (``page.md#heading``) names a heading of that page, spelt as GitHub makes its anchors."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from .conftest import REPO

PAGES = sorted([REPO / "README.md", REPO / "config" / "README.md", *(REPO / "docs").glob("*.md"),
                *(REPO / "src" / "roughlight").glob("*/README.md")])

#: [text](target) and ![alt](target), but not inside inline code.
LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)\)")


def anchors(page: Path) -> set[str]:
    """GitHub's anchor of every heading of ``page``: lower case, punctuation but ``-`` and ``_`` dropped, spaces to
    hyphens (a heading met twice gets ``-1``, ``-2``, ...)."""
    seen: dict[str, int] = {}
    out = set()
    in_code = False
    for line in page.read_text(encoding="utf-8").splitlines():
        if line.startswith("```"):
            in_code = not in_code
        if in_code or not line.startswith("#"):
            continue
        text = line.lstrip("#").strip().lower()
        slug = re.sub(r"[^\w\- ]", "", text).replace(" ", "-")
        n = seen.get(slug, 0)
        seen[slug] = n + 1
        out.add(slug if n == 0 else f"{slug}-{n}")
    return out


def links(page: Path) -> list[str]:
    """The relative link targets of ``page``, code blocks and inline code left out."""
    text = re.sub(r"```.*?```", "", page.read_text(encoding="utf-8"), flags=re.S)
    text = re.sub(r"`[^`\n]*`", "", text)
    return [t for t in LINK.findall(text) if not re.match(r"[a-z]+:", t)]


def test_the_slug_is_githubs():
    page = REPO / "docs" / "running.md"
    assert {"kill-safety-and-the-run-lock", "reruns-and-what-stops-a-run-before-it-renders"} <= anchors(page)
    assert "what-make-test-checks" in anchors(REPO / "docs" / "README.md")


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.relative_to(REPO).as_posix())
def test_every_relative_link_resolves(page):
    found = links(page)
    if page.name == "README.md" and page.parent == REPO:
        assert len(found) > 10  # the front door links its docs: the pattern finds them
    for target in found:
        path, _, fragment = target.partition("#")
        where = (page.parent / path).resolve() if path else page
        assert where.exists(), f"{page.relative_to(REPO)}: {target} names no file"
        if fragment and where.suffix == ".md":
            assert fragment in anchors(where), f"{page.relative_to(REPO)}: {target} names no heading of {path}"
