"""Generated files: compare with, or write, what their renderers give (the generators in scripts/).

A generator maps each output path (relative to the repository root) to a function that renders its text;
:func:`stale` lists the outputs that are missing or differ (the ``--check`` modes and the up-to-date
tests), :func:`write_all` renders everything first and then writes it.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from pathlib import Path


def stale(renderers: Mapping[str, Callable[[], str]], repo_root: Path) -> list[str]:
    """``<path>: missing`` or ``<path>: differs`` for each output that is not what its renderer gives."""
    problems = []
    for rel, fn in renderers.items():
        path = repo_root / rel
        if not path.is_file():
            problems.append(f"{rel}: missing")
        elif path.read_text(encoding="utf-8") != fn():
            problems.append(f"{rel}: differs")
    return problems


def write_all(renderers: Mapping[str, Callable[[], str]], repo_root: Path) -> list[str]:
    """Render every output, then write them all; returns the paths written."""
    texts = {rel: fn() for rel, fn in renderers.items()}
    for rel, text in texts.items():
        (repo_root / rel).parent.mkdir(parents=True, exist_ok=True)
        (repo_root / rel).write_text(text, encoding="utf-8")
    return list(texts)
