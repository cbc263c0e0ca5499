"""Consoles whose tables fit where they are printed.

On a terminal, rich measures its width (``COLUMNS`` overrides it) and the tables drop
columns to fit, wrapping long cells. Piped or redirected, the output is plain text: no
colour, no cursor codes, ASCII table borders instead of box-drawing characters, at
``COLUMNS`` columns or :data:`PLAIN_WIDTH`; long notes wrap inside their cells rather
than widening the table.
"""

from __future__ import annotations

import os

from rich.console import Console

#: Width of plain (piped or redirected) output when ``COLUMNS`` does not say.
PLAIN_WIDTH = 100


class PlainConsole(Console):
    """A console for files and pipes: rich picks ASCII borders for an ASCII encoding."""

    @property
    def encoding(self) -> str:
        return "ascii"


def plain_width() -> int:
    """``COLUMNS`` when it is a positive number, else :data:`PLAIN_WIDTH`."""
    text = os.environ.get("COLUMNS", "").strip()
    return int(text) if text.isdigit() and int(text) > 0 else PLAIN_WIDTH


def output_console(stderr: bool = False) -> Console:
    """A console for stdout (or stderr) that fits the terminal, or plain text if piped."""
    console = Console(stderr=stderr)
    if console.is_terminal:
        return console
    return PlainConsole(stderr=stderr, width=plain_width(), no_color=True, highlight=False,
                        emoji=False, soft_wrap=True)


def fits(console: Console, needed: int) -> bool:
    """Whether ``needed`` columns of text fit in ``console``'s width."""
    return console.width >= needed
