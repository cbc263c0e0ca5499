"""MkDocs hooks (``hooks:`` in mkdocs.yml): the pages generated from the code, and math.

- ``rules.md`` is generated from the rule registry (``urdfinertia.rules``) on every build:
  one section per rule, anchored by its id (``rules/#ui111``), so the page cannot drift from
  the registry and SARIF's ``helpUri`` has somewhere to point.
- ``<!-- generated: cli-python -->`` in a page is replaced by the table of every command
  line option and its Python equivalent, built from the argument parser and
  ``urdfinertia.cli.options.PYTHON_EQUIVALENTS``.
- Math (``$...$``, ``$$...$$``, which pymdownx.arithmatex marks) is rendered to MathML at
  build time with latex2mathml: the site needs no script and no network to show it.
"""

from __future__ import annotations

import argparse
import html
import re
from pathlib import Path
from typing import Any

RULES_PAGE = "rules.md"
CLI_MARKER = "<!-- generated: cli-python -->"

#: arithmatex's generic output: inline spans and display blocks holding escaped TeX
_INLINE_MATH = re.compile(r'<span class="arithmatex">\\\((.*?)\\\)</span>', re.DOTALL)
_BLOCK_MATH = re.compile(r'<div class="arithmatex">\\\[(.*?)\\\]</div>', re.DOTALL)


# --- the rules page -------------------------------------------------------------------

def _member_docs(class_name: str) -> dict[str, str]:
    """The docstrings of an Enum's members in urdfinertia.rules (read from the source:
    attribute docstrings exist only there)."""
    import griffe

    # the module's file alone, statically: no import of the package, no inspection
    module = griffe.visit("rules", filepath=Path(registry_file()),
                          code=Path(registry_file()).read_text(encoding="utf-8"))
    members = module[class_name].members
    return {name: " ".join(m.docstring.value.split()) if m.docstring else ""
            for name, m in members.items() if not name.startswith("_")}


def registry_file() -> str:
    """The source file of the rule registry."""
    import urdfinertia.rules

    return urdfinertia.rules.__file__


def _blocks(doc: str) -> dict[str, str]:
    """The block titles the registry's module docstring gives ("UI2xx: against the
    geometry" -> {"2": "against the geometry"})."""
    flat = " ".join(doc.split())
    return {m.group(1): m.group(2).strip() for m in
            re.finditer(r"UI(\d)xx: ([^;.]+(?:\([^)]*\))?[^;.]*)", flat)}


def _escape_cell(text: str) -> str:
    return text.replace("|", "\\|").replace("<", "&lt;").replace(">", "&gt;")


def _inline(text: str) -> str:
    """Registry text into Markdown prose: tags outside code spans escaped."""
    parts = re.split(r"(`[^`]*`)", text)
    return "".join(p if p.startswith("`") else p.replace("<", "&lt;").replace(">", "&gt;")
                   for p in parts)


def _lower_first(text: str) -> str:
    return text[:1].lower() + text[1:]


def rules_markdown() -> str:
    """The rules page: an index table, then one section per rule, every one anchored."""
    import urdfinertia.rules as registry
    from urdfinertia.rules import FixAction, Rule, Scope, Severity

    fix_docs = _member_docs("FixAction")
    scope_docs = _member_docs("Scope")
    severity_docs = _member_docs("Severity")
    titles = _blocks(registry.__doc__ or "")
    out = [
        "# Rules",
        "",
        "Every finding `check` prints (and `fix` acts on) belongs to one rule: a stable id",
        "(`UI111`), a code (`placeholder-inertia`) and a severity. This page is generated",
        "from the rule registry (`urdfinertia.rules`) when the site is built; SARIF's",
        "`helpUri` of each rule points at its section here.",
        "",
        "Severities: " + "; ".join(
            f"**{s.value}**: {_inline(_lower_first(severity_docs.get(s.name, '')).rstrip('.'))}"
            for s in Severity) + ".",
        "",
        "What `fix` does about a rule's findings (default options):",
        "",
    ]
    out += [f"- **{a.value}**: {_inline(fix_docs.get(a.name, ''))}" for a in FixAction]
    out += ["", "| id | code | severity | fix | summary |", "|---|---|---|---|---|"]
    for rule in Rule:
        out.append(f"| [{rule.id}](#{rule.anchor}) | `{rule.value}` | {rule.severity.value} "
                   f"| {rule.fix.value} | {_escape_cell(rule.summary)} |")
    block = None
    for rule in Rule:
        if rule.id[2] != block:
            block = rule.id[2]
            title = titles.get(block)
            out += ["", f"## UI{block}xx" + (f": {title}" if title else ""), ""]
        scope = scope_docs.get(Scope(rule.scope).name, "").rstrip(".")
        out += [
            f"### {rule.id} {rule.value} {{#{rule.anchor}}}",
            "",
            f"**{rule.severity.value}** · points at {_inline(scope[:1].lower() + scope[1:])}"
            f" · fix: **{rule.fix.value}**",
            "",
            _inline(rule.summary[:1].upper() + rule.summary[1:]) + ".",
            "",
            _inline(rule.meaning),
            "",
            "Example:",
            "",
            "```text",
            rule.example,
            "```",
            "",
            f"**What fix does:** {_inline(fix_docs.get(rule.fix.name, rule.fix.value))}",
            "",
            f"**To silence it:** {_inline(rule.silence[:1].upper() + rule.silence[1:])}.",
            "",
        ]
    return "\n".join(out) + "\n"


# --- the command line in Python ---------------------------------------------------------

def _subparsers() -> dict[str, argparse.ArgumentParser]:
    from urdfinertia.cli import build_parser

    parser, _ = build_parser()
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            return dict(action.choices)
    raise RuntimeError("the command line has no subcommands")


def cli_options() -> list[tuple[str, str, argparse.Action]]:
    """Every (command, option name, action) of the command line, in the parser's order;
    the option name is its long form, a positional argument's name its dest."""
    found = []
    for command, sub in _subparsers().items():
        for action in sub._actions:
            if isinstance(action, argparse._HelpAction):
                continue
            longs = [o for o in action.option_strings if o.startswith("--")]
            name = longs[0] if longs else (action.option_strings[0] if action.option_strings
                                           else action.dest)
            found.append((command, name, action))
    return found


def cli_python_markdown() -> str:
    """One table per command: each option, its help and how it is said in Python."""
    from urdfinertia.cli.options import python_equivalent

    out: list[str] = []
    current = None
    for command, name, action in cli_options():
        if command != current:
            current = command
            out += ["", f"#### `urdf-inertia {command}` and `urdfinertia.{command}`", "",
                    "| option | Python |", "|---|---|"]
        shown = ", ".join(action.option_strings) if action.option_strings else name.upper()
        if action.metavar and action.option_strings:
            shown += f" {action.metavar}"
        python = python_equivalent(command, name)
        if python is None:
            raise RuntimeError(f"{command} {name}: no entry in PYTHON_EQUIVALENTS")
        out.append(f"| `{shown}` | {_escape_cell(python).replace('&lt;', '<')} |")
    return "\n".join(out) + "\n"


# --- math -------------------------------------------------------------------------------

def render_math(page_html: str) -> str:
    """arithmatex's TeX spans into MathML (inline and display)."""
    if "arithmatex" not in page_html:
        return page_html
    from latex2mathml.converter import convert

    def block(m: re.Match[str]) -> str:
        return convert(html.unescape(m.group(1)).strip(), display="block")

    def inline(m: re.Match[str]) -> str:
        return convert(html.unescape(m.group(1)).strip())

    return _INLINE_MATH.sub(inline, _BLOCK_MATH.sub(block, page_html))


# --- the hooks --------------------------------------------------------------------------

def on_files(files: Any, config: Any) -> Any:
    from mkdocs.structure.files import File

    files.append(File.generated(config, RULES_PAGE, content=rules_markdown()))
    return files


def on_page_markdown(markdown: str, page: Any, config: Any, files: Any) -> str:
    if CLI_MARKER in markdown:
        markdown = markdown.replace(CLI_MARKER, cli_python_markdown())
    return markdown


def on_page_content(html_text: str, page: Any, config: Any, files: Any) -> str:
    return render_math(html_text)
