"""Consoles whose tables fit where they are printed.

On a terminal, rich measures its width and the tables drop columns to fit (never wrap
rows). Piped or redirected, the output is plain text (no colour, no cursor codes) as wide
as its content needs, so no word is ever wrapped across lines.
"""

from __future__ import annotations

from rich.console import Console

#: Width given to rich when the output is not a terminal: wide enough never to wrap.
PLAIN_WIDTH = 10_000


def output_console(stderr: bool = False) -> Console:
    """A console for stdout (or stderr) that fits the terminal, or plain text if piped."""
    console = Console(stderr=stderr)
    if console.is_terminal:
        return console
    return Console(stderr=stderr, width=PLAIN_WIDTH, no_color=True, highlight=False,
                   emoji=False, soft_wrap=True)


def fits(console: Console, needed: int) -> bool:
    """Whether ``needed`` columns of text fit in ``console``'s width."""
    return console.width >= needed
