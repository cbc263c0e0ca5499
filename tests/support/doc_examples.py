"""The runnable examples of README.md and docs/*.md: find them, run them, compare, rewrite.

The convention (also stated in ``docs/contributing.md``):

- A fenced block marked ```` ```console ```` is a shell session. Each line starting with
  ``$ `` is a command (a trailing ``\\`` continues it on the next line); the lines after it,
  up to the next command, are what it printed (stdout and stderr together). A command
  expects exit code 0 unless it ends with a comment ``# exit N``.
- A fenced block marked ```` ```python ```` is executed; the blocks of one page share one
  namespace, in page order, so a later block may use what an earlier one defined. Examples
  state their facts with ``assert``.
- Blocks in any other language (``sh``, ``text``, ``toml``, ``yaml``, ...) are syntax
  templates, files or abridged illustrations, and are not run.
- A block shows the whole output of its commands: nothing is filtered out of it. A command
  whose output is too long for the page cuts it itself, where the reader sees it
  (``| head -n 12``), and the page says so. Output is generated :data:`WIDTH` columns wide,
  what the site's content column holds.

Every page runs in a fresh folder holding a copy of the repository's ``robots/`` folder,
with ``ERD`` set to example-robot-data's ``robots`` folder and the ``urdf-inertia`` of this
interpreter's environment first on ``PATH``. Paths of that folder and of ``ERD`` are written
as ``$ERD`` and left out when outputs are compared or rewritten.

What is checked: the exit code, that the documented output has as many lines as the real
run printed (nothing left out), and that every number it shows is also printed by the real
run (loosely: the layout of a line is not compared).
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from support.corpus import example_robot_data_robots

ROOT = Path(__file__).resolve().parents[2]
RUN_LANGUAGES = ("console", "python")
_FENCE = re.compile(r"^(`{3,})([\w+-]*)\s*$")
#: An abridging comment of an older convention: refused (a page must show what ran).
_KEEP = re.compile(r"^<!--\s*keep:")
_EXIT = re.compile(r"#\s*exit\s+(\d+)\b")
#: Numbers as printed: integers, decimals and exponents (``1.175e-06``, ``-0.0475``, ``81``).
_NUMBER = re.compile(r"(?<![\w.])-?\d+(?:\.\d+)?(?:e[-+]?\d+)?")
#: Columns of the examples' output: the tool's tables (and other tools) fit the site's
#: content column at this width (docs/stylesheets/extra.css), so no block is cut sideways.
WIDTH = 100
_ENV_EXTRA = {"COLUMNS": str(WIDTH), "NO_COLOR": "1", "TERM": "dumb", "PYTHONHASHSEED": "0"}


def doc_files() -> list[Path]:
    """README.md and every page of the site, in a stable order."""
    return [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]


@dataclass
class Command:
    text: str  # the command as typed, continuation lines joined
    output: list[str]  # the documented output lines
    exit_code: int


@dataclass
class Block:
    path: Path
    line: int  # 1-based line of the opening fence
    language: str
    lines: list[str]  # the block's content
    commands: list[Command] = field(default_factory=list)

    @property
    def where(self) -> str:
        return f"{self.path.relative_to(ROOT)}:{self.line}"


def blocks(path: Path) -> list[Block]:
    """The runnable blocks of one Markdown file (unindented fences only)."""
    found: list[Block] = []
    lines = path.read_text(encoding="utf-8").splitlines()
    i = 0
    while i < len(lines):
        m = _FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        fence, language = m.group(1), m.group(2)
        end = i + 1
        while end < len(lines) and lines[end].rstrip() != fence:
            end += 1
        if language in RUN_LANGUAGES:
            if i > 0 and _KEEP.match(lines[i - 1]):
                raise ValueError(f"{path.name}:{i}: a 'keep:' comment filters the output a "
                                 "reader would see; show it whole or cut it in the command")
            block = Block(path, i + 1, language, lines[i + 1:end])
            if language == "console":
                block.commands = _commands(block)
            found.append(block)
        i = end + 1
    return found


def _commands(block: Block) -> list[Command]:
    commands: list[Command] = []
    lines = iter(block.lines)
    for line in lines:
        if line.startswith("$ "):
            text = line[2:]
            while text.endswith("\\"):
                text = text[:-1] + " " + next(lines).strip()
            m = _EXIT.search(text)
            commands.append(Command(text, [], int(m.group(1)) if m else 0))
        elif commands:
            commands[-1].output.append(line)
        else:
            raise ValueError(f"{block.where}: a console block must start with '$ '")
    return commands


class Workspace:
    """A fresh folder with a copy of ``robots/``: where one page's examples run."""

    def __init__(self) -> None:
        self.dir = Path(tempfile.mkdtemp(prefix="urdfinertia-docs-"))
        shutil.copytree(ROOT / "robots", self.dir / "robots")
        self.erd = example_robot_data_robots()
        bindir = str(Path(sys.executable).parent)
        self.env = {**os.environ, **_ENV_EXTRA, "ERD": str(self.erd),
                    "PATH": bindir + os.pathsep + os.environ.get("PATH", ""),
                    "URDFINERTIA_CACHE_DIR": str(self.dir / ".cache")}
        self.namespace: dict[str, object] = {"__name__": "__doc_example__"}

    def close(self) -> None:
        shutil.rmtree(self.dir, ignore_errors=True)

    def clean(self, text: str) -> str:
        """Machine paths out: the workspace and example-robot-data's folder."""
        text = text.replace(str(self.erd), "$ERD")
        text = text.replace(str(self.dir) + os.sep, "").replace(str(self.dir), ".")
        return text

    def run(self, command: Command, timeout: float = 120.0) -> tuple[int, list[str]]:
        # stderr joins stdout on the same pipe, as on a terminal; a redirection inside the
        # command (`> file`) still takes stdout alone
        done = subprocess.run(["bash", "-c", command.text], cwd=self.dir, env=self.env,
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                              timeout=timeout)
        lines = [ln.rstrip() for ln in self.clean(done.stdout).splitlines()]
        return done.returncode, lines

    def exec_python(self, block: Block) -> None:
        code = compile("\n".join(block.lines) + "\n", block.where, "exec")
        cwd = os.getcwd()
        saved = {k: os.environ.get(k) for k in ("ERD", "URDFINERTIA_CACHE_DIR")}
        os.environ.update(ERD=self.env["ERD"], URDFINERTIA_CACHE_DIR=self.env[
            "URDFINERTIA_CACHE_DIR"])
        os.chdir(self.dir)
        try:
            exec(code, self.namespace)  # noqa: S102 - the documentation's own examples
        finally:
            os.chdir(cwd)
            for k, v in saved.items():
                if v is None:
                    os.environ.pop(k, None)
                else:
                    os.environ[k] = v


def numbers(lines: list[str]) -> set[str]:
    """The numbers printed in ``lines``, as printed."""
    return {m.group(0) for line in lines for m in _NUMBER.finditer(line)}


#: Significant digits from which a printed number is a float's full ``repr``: such a number
#: may differ in its last digits between machines (another CPU takes other SIMD paths
#: through numpy's sums), so it matches any printed number within this relative distance.
_FULL_REPR_DIGITS = 12
_ROUND_OFF = 1e-11


def _digits(text: str) -> int:
    mantissa = text.lstrip("-").split("e")[0].replace(".", "").lstrip("0")
    return len(mantissa)


def unmatched(shown: set[str], printed: set[str]) -> set[str]:
    """The numbers a page shows that the run did not print: as printed, except that a
    full-precision float may differ from a printed one by round-off."""
    missing = shown - printed
    floats = [float(p) for p in printed if _digits(p) >= _FULL_REPR_DIGITS]
    return {m for m in missing
            if _digits(m) < _FULL_REPR_DIGITS
            or not any(abs(float(m) - f) <= _ROUND_OFF * abs(f) for f in floats)}


def check_command(ws: Workspace, block: Block, command: Command) -> list[str]:
    """The differences between a documented command and its real run (empty: it agrees)."""
    code, lines = ws.run(command)
    problems = []
    if code != command.exit_code:
        problems.append(f"{block.where}: `{command.text}` exited {code}, the page says "
                        f"{command.exit_code}; it printed:\n" + "\n".join(lines[-15:]))
    if len(command.output) != len(lines):
        problems.append(f"{block.where}: `{command.text}` printed {len(lines)} line(s), the "
                        f"page shows {len(command.output)}: show the whole output (or cut it "
                        "in the command, `| head -n N`); regenerate with "
                        "scripts/regen_docs.py")
    missing = unmatched(numbers(command.output), numbers(lines))
    if missing:
        problems.append(f"{block.where}: `{command.text}` no longer prints "
                        f"{sorted(missing)}; regenerate with scripts/regen_docs.py")
    return problems


_RELATIVE_PACKAGE_DIR = re.compile(r"(--package-dir\s+[\w.-]+=)(?![/$~])(\S+)")
_RELATIVE_DIRS_ENTRY = re.compile(r'("[\w.-]+"):\s*"(?![/$~])([^"]+)"')


def absolute_package_dirs(block: Block) -> Block:
    """The block with every relative package folder made absolute (from the working
    directory): ``--package-dir NAME=DIR`` in commands, ``{"NAME": "DIR"}`` entries of the
    Python assignments to a name of package folders (``dirs = {...}``)."""
    if block.language == "python":
        lines = [_RELATIVE_DIRS_ENTRY.sub(r'\1: __import__("os").path.abspath("\2")', ln)
                 if re.match(r"\s*\w*dirs\s*=\s*\{", ln) else ln for ln in block.lines]
        return Block(block.path, block.line, block.language, lines)
    commands = [Command(_RELATIVE_PACKAGE_DIR.sub(r"\1$PWD/\2", c.text), c.output,
                        c.exit_code) for c in block.commands]
    return Block(block.path, block.line, block.language, block.lines, commands)


def check_file(path: Path, *, absolute_dirs: bool = False) -> list[str]:
    """Run every example of one page; the problems found (empty: all agree).

    ``absolute_dirs`` runs the page with its relative package folders made absolute
    (:func:`absolute_package_dirs`): what tells a failure of the resolution of relative
    ``--package-dir`` folders from any other.
    """
    ws = Workspace()
    problems: list[str] = []
    try:
        for block in blocks(path):
            if absolute_dirs:
                block = absolute_package_dirs(block)
            if block.language == "python":
                ws.exec_python(block)
                continue
            for command in block.commands:
                problems += check_command(ws, block, command)
    finally:
        ws.close()
    return problems


def regenerate(path: Path, *, absolute_dirs: bool = False) -> int:
    """Rerun a page's console blocks and write their real output into it; commands run.

    ``absolute_dirs``: run them with relative package folders made absolute (the page
    keeps them as written; see :func:`check_file`)."""
    text = path.read_text(encoding="utf-8").splitlines()
    ws = Workspace()
    replaced: dict[int, list[str]] = {}  # fence line index -> new block content
    count = 0
    try:
        for block in blocks(path):
            if absolute_dirs:
                block = absolute_package_dirs(block)
            if block.language == "python":
                ws.exec_python(block)
                continue
            body: list[str] = []
            raw = iter(block.lines)
            for command in block.commands:
                # the command lines as written (continuations kept)
                for line in raw:
                    if line.startswith("$ "):
                        body.append(line)
                        while body[-1].endswith("\\"):
                            body.append(next(raw))
                        break
                code, lines = ws.run(command)
                if code != command.exit_code:
                    raise SystemExit(f"{block.where}: `{command.text}` exited {code}, "
                                     f"expected {command.exit_code}:\n" + "\n".join(lines))
                body += lines
                count += 1
            replaced[block.line - 1] = body
    finally:
        ws.close()
    out: list[str] = []
    i = 0
    while i < len(text):
        if i in replaced:
            out.append(text[i])
            fence = _FENCE.match(text[i]).group(1)  # type: ignore[union-attr]
            out += replaced[i]
            i += 1
            while text[i].rstrip() != fence:
                i += 1
            out.append(text[i])
        else:
            out.append(text[i])
        i += 1
    path.write_text("\n".join(out) + "\n", encoding="utf-8")
    return count
