"""Expand a xacro document in-process with the `xacro` package, hardened and traced.

`xacro` (PyPI, no ROS needed) keeps its state in module globals and reads files itself,
so one expansion at a time runs under a lock with four hooks in place:

* `xacro.parse` (the main file and every `<xacro:include>`): the file is checked like
  any description (size limit, no entity declarations, no external DTD, no UTF-16/32:
  `hostile_xml_cause`) before expat sees it, URLs are
  refused, and every element is tagged with where it was written (source file, byte
  offset of its start tag).
* `xacro.load_yaml`: the same refusals for YAML (size, URLs); `yaml.safe_load`.
* Both read only regular files (opened without blocking: a FIFO or device is refused)
  under the folders the robot may read: the main file's folder tree (and its package's,
  the nearest folder above with a `package.xml`), the `--package-dir` folders and the
  packages `$(find)` or `package://` resolved. Anything else (`/etc/passwd`) is refused.
* `xacro.safe_eval`: `**` and `<<` go through bounded functions: an integer result of
  more than `MAX_INTEGER_BITS` bits (`${10**(10**8)}`) is refused, not computed.
* `$(find PKG)`: the tool's own package lookup (`
  find_package`: `--package-dir`, `ROS_PACKAGE_PATH`, `AMENT_PREFIX_PATH`, the
  folders above the file).
* `xacro.eval_all`: an error is located at the innermost element whose source is known,
  and the number of evaluated elements is bounded (a macro bomb stops, it does not fill
  memory).

The tags survive macro expansion (an element copied out of a macro body keeps the tag of
the body's element), which gives the *trace*: for each element of the expanded URDF, the
source element it was copied from. Write-back (`.writeback`) uses it, and errors of
the URDF reader are mapped back to the xacro line through it. `overrides` replaces the
bytes of source files without touching the disk (write-back's perturbed expansions).
"""

from __future__ import annotations

import ast
import contextlib
import functools
import io
import math
import os
import re
import stat
import threading
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any
from xml.dom import expatbuilder, minidom
from xml.parsers import expat

from urdfinertia.descriptions.xacro.settings import (  # noqa: F401 - this module's API too
    XacroSettings,
    configure,
    current_settings,
    settings_for,
)
from urdfinertia.descriptions.xml import MAX_DOCUMENT_BYTES, hostile_xml_cause
from urdfinertia.errors import UrdfError, UrdfInertiaError

SOURCE_ATTR = "urdfinertia-src"
"""Attribute carrying an element's source during expansion; removed from the output."""
MAX_EVALUATED_ELEMENTS = 2_000_000
"""Elements evaluated in one expansion before it is refused (real robots: < 20,000)."""
MAX_INTEGER_BITS = 4096
"""Largest integer `**` or `<<` may make in a xacro expression (10**1000 is 3,322 bits)."""
_URL = re.compile(r"(?<![A-Za-z0-9+.\-])[A-Za-z][A-Za-z0-9+.\-]*://")
"""A URL's scheme; it starts only where a run of scheme characters starts (linear time on a
megabyte of letters, where a plain search is quadratic)."""
MAX_NAME = 4096
"""Longest file name xacro may ask for (PATH_MAX)."""
_LOCK = threading.RLock()


@dataclass(frozen=True)
class Expansion:
    """One expansion: the URDF bytes and where each of its elements was written.

    Attributes
    ----------
    document : bytes
        The URDF xacro made.
    sources : tuple of Path
        Every file xacro read, in reading order (main file first), resolved.
    source_bytes : tuple of bytes
        Their contents as read (after `overrides`).
    locations : tuple of (int, int) or None
        Per element of `document`, in document order: (index into `sources`, byte offset
        of the start tag's `<`), or None (an element made by `xacro:element` ...).
    warnings : str
        What xacro printed while expanding.
    """

    document: bytes
    sources: tuple[Path, ...]
    source_bytes: tuple[bytes, ...]
    locations: tuple[tuple[int, int] | None, ...]
    warnings: str = ""

    def where(self, location: tuple[int, int] | None) -> str:
        """`file:line` of a location."""
        if location is None:
            return "?"
        index, offset = location
        return f"{self.sources[index]}:{line_of(self.source_bytes[index], offset)}"


def line_of(data: bytes, offset: int) -> int:
    """The 1-based line of byte `offset` of `data`.

    Parameters
    ----------
    data : bytes
        A file's contents.
    offset : int
        A byte offset.

    Returns
    -------
    int
        Its line.
    """
    return data.count(b"\n", 0, offset) + 1


@dataclass
class _State:
    overrides: Mapping[str, bytes]
    settings: XacroSettings
    main_dir: Path
    #: real folders whose files xacro may read (grows as packages are found)
    allowed: list[str] = field(default_factory=list)
    sources: list[Path] = field(default_factory=list)
    source_bytes: list[bytes] = field(default_factory=list)
    evaluated: int = 0


class _LocatingBuilder(expatbuilder.ExpatBuilderNS):
    """minidom builder that records each element's source (file index, byte offset)."""

    def __init__(self, source_index: int) -> None:
        super().__init__()
        self._source_index = source_index

    def start_element_handler(self, name, attributes):  # noqa: ANN001, ANN201 - expat's
        super().start_element_handler(name, attributes)
        node = self.curNode
        where = (self._source_index, self._parser.CurrentByteIndex)
        node._urdfinertia_src = where  # survives on originals only (not on clones)
        if not node.tagName.startswith("xacro:"):
            # an XML attribute is copied with the element out of macro bodies and blocks
            node.setAttribute(SOURCE_ATTR, f"{where[0]}:{where[1]}")


_PACKAGE_URI = re.compile(r"package://([^/]*)/(.*)\Z", re.S)
_FILE_URI = re.compile(r"file://(?:localhost)?(/.*)\Z", re.S)


def _local_path(text: str, state: _State) -> str:
    """The file a name xacro asks for denotes: `package://` through the package lookup
    (xacro itself would join it to the including file's folder), `file://` as a path;
    any other URL is refused."""
    from urdfinertia.descriptions.paths import find_package, package_hint

    if len(text) > MAX_NAME:
        raise UrdfError(f"a file name of {len(text)} characters (more than {MAX_NAME}): "
                        f"{text[:60]!r}...")
    scheme = _URL.search(text)
    if scheme is None:
        return text
    uri = text[scheme.start():]
    package = _PACKAGE_URI.match(uri)
    if package is not None:
        found = find_package(package.group(1), state.main_dir,
                             {k: Path(v) for k, v in state.settings.package_dirs})
        if found is None:
            raise UrdfError(f"{uri}: package '{package.group(1)}' not found: "
                            f"{package_hint(package.group(1))} or set ROS_PACKAGE_PATH")
        state.allowed.append(os.path.realpath(found))
        return str(found / package.group(2))
    local = _FILE_URI.match(uri)
    if local is not None:
        return local.group(1)
    raise UrdfError(f"xacro reads only local files, not URLs: {uri!r}")


def allowed_folders(main_dir: Path, settings: XacroSettings) -> list[str]:
    """The real folders a xacro expansion starts allowed to read: the main file's, its
    package's (the nearest folder above with a `package.xml`) and the `--package-dir`
    folders."""
    main = os.path.realpath(main_dir)
    out = [main, *(os.path.realpath(v) for _, v in settings.package_dirs)]
    for folder in Path(main).parents:
        if (folder / "package.xml").is_file():
            out.append(str(folder))
            break
    return out


def _inside(real: str, folders: list[str]) -> bool:
    return any(real == f or real.startswith(f.rstrip(os.sep) + os.sep) for f in folders)


def read_source(path: str | Path, state: _State) -> bytes:
    """A file xacro asks for: refused if it is a URL, outside the allowed folders, not a
    regular file, too large or hostile XML."""
    text = _local_path(os.fspath(path), state)
    real = os.path.realpath(text)
    if real in state.overrides:
        data = state.overrides[real]
    else:
        if not _inside(real, state.allowed):
            raise UrdfError(f"xacro reads only files under the robot's folder, its "
                            f"package, --package-dir folders and found packages, not "
                            f"{text!r}")
        # OSError: xacro's optional includes depend on it; non-blocking: a FIFO's open
        # would wait for a writer
        fd = os.open(text, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_BINARY", 0))
        with os.fdopen(fd, "rb") as fh:
            if not stat.S_ISREG(os.fstat(fd).st_mode):
                raise UrdfError(f"xacro reads only regular files, not {text!r} (a FIFO, "
                                "device or folder)")
            data = fh.read(MAX_DOCUMENT_BYTES + 1)
    if len(data) > MAX_DOCUMENT_BYTES:
        raise UrdfError(f"file is larger than the limit of {MAX_DOCUMENT_BYTES} bytes",
                        file=text)
    state.sources.append(Path(real))
    state.source_bytes.append(data)
    return data


def _hooks(state: _State) -> dict[str, Any]:
    import xacro
    import yaml

    def parse(inp, filename=None):  # noqa: ANN001, ANN202 - xacro's signature
        if inp is not None:
            return original_parse(inp, filename)
        try:
            data = read_source(os.path.join(xacro.root_dir, filename), state)
        except OSError as exc:
            xacro.filestack.pop()  # as xacro.parse: an optional include may be missing
            raise xacro.XacroException(f"{exc.strerror}: {exc.filename}", exc=exc) from None
        cause = hostile_xml_cause(data)
        if cause:
            raise UrdfError(cause, file=filename)
        try:
            return _LocatingBuilder(len(state.sources) - 1).parseString(data)
        except expat.ExpatError as exc:
            raise UrdfError(f"malformed XML: {expat.ErrorString(exc.code)}", file=filename,
                            line=exc.lineno) from None

    def load_yaml(filename):  # noqa: ANN001, ANN202
        for unit in xacro.ConstructUnits:
            yaml.SafeLoader.add_constructor(unit.value.tag, unit.constructor)
        filename = xacro.abs_filename_spec(filename)
        try:
            data = read_source(filename, state)
        except OSError as exc:
            raise xacro.XacroException(f"{exc.strerror}: {exc.filename}", exc=exc) from None
        xacro.filestack.append(filename)
        try:
            return xacro.YamlListWrapper.wrap(yaml.safe_load(data))
        except yaml.YAMLError as exc:
            mark = getattr(exc, "problem_mark", None)
            raise UrdfError(f"invalid YAML: {getattr(exc, 'problem', None) or exc}",
                            file=filename, line=mark.line + 1 if mark else None) from None
        finally:
            xacro.filestack.pop()

    def find(package):  # noqa: ANN001, ANN202
        from urdfinertia.descriptions.paths import find_package, package_hint

        found = find_package(package, state.main_dir, dict(state.settings.package_dirs))
        if found is None:
            raise UrdfError(f"$(find {package}): package not found: "
                            f"{package_hint(package)} or set ROS_PACKAGE_PATH")
        state.allowed.append(os.path.realpath(found))
        return str(found)

    def eval_all(node, macros, symbols):  # noqa: ANN001, ANN202
        state.evaluated += 1
        if state.evaluated > MAX_EVALUATED_ELEMENTS:
            raise UrdfError(f"expansion evaluates more than {MAX_EVALUATED_ELEMENTS} "
                            "elements (macro recursion or bomb?)")
        with _locating(node):
            return original["eval_all"](node, macros, symbols)

    def located(name: str):  # noqa: ANN202 - xacro's handlers of one element each
        def handler(node, *args):  # noqa: ANN001, ANN202
            with _locating(node):
                return original[name](node, *args)
        return handler

    original = {name: getattr(xacro, name) for name in _LOCATED}
    original_parse = xacro.parse
    hooks = {name: located(name) for name in _LOCATED}
    hooks.update(parse=parse, load_yaml=load_yaml, find=find, eval_all=eval_all,
                 safe_eval=functools.partial(bounded_eval, original_safe_eval=xacro.safe_eval))
    return hooks


_BOUNDED = {ast.Pow: "_urdfinertia_pow", ast.LShift: "_urdfinertia_lshift"}


class _BoundOperators(ast.NodeTransformer):
    """`a ** b` -> `_urdfinertia_pow(a, b)`, `a << b` likewise."""

    def visit_BinOp(self, node: ast.BinOp) -> ast.AST:
        self.generic_visit(node)
        name = _BOUNDED.get(type(node.op))
        if name is None:
            return node
        return ast.copy_location(ast.Call(ast.Name(name, ast.Load()), [node.left, node.right],
                                          []), node)


def _too_large(what: str) -> UrdfError:
    return UrdfError(f"xacro: {what} makes an integer of more than {MAX_INTEGER_BITS} bits "
                     "(refused, not computed)")


def _bounded_pow(base: Any, exponent: Any) -> Any:
    if (isinstance(base, int) and isinstance(exponent, int) and exponent > 0
            and abs(base) > 1 and exponent * math.log2(abs(base)) > MAX_INTEGER_BITS):
        raise _too_large(f"{base} ** {exponent}")
    return base ** exponent


def _bounded_lshift(value: Any, shift: Any) -> Any:
    if isinstance(value, int) and isinstance(shift, int) and value and shift > MAX_INTEGER_BITS:
        raise _too_large(f"{value} << {shift}")
    return value << shift


def bounded_eval(expr: str, globals: Any, locals: Any = None, *,  # noqa: A002 - xacro's
                 original_safe_eval: Any) -> Any:
    """xacro's `safe_eval` with `**` and `<<` bounded (`MAX_INTEGER_BITS`)."""
    tree = ast.parse(expr.strip(), "<expression>", "eval")
    if not any(isinstance(n, ast.BinOp) and type(n.op) in _BOUNDED for n in ast.walk(tree)):
        return original_safe_eval(expr, globals, locals)
    code = compile(ast.fix_missing_locations(_BoundOperators().visit(tree)), "<expression>",
                   "eval")
    invalid = [n for n in code.co_names if n.startswith("__")]
    if invalid:
        return original_safe_eval(expr, globals, locals)  # xacro's own refusal
    globals.update(__builtins__={"_urdfinertia_pow": _bounded_pow,
                                 "_urdfinertia_lshift": _bounded_lshift})
    try:
        return eval(code, globals, locals)  # noqa: S307 - xacro's restricted namespace
    finally:
        globals.update(__builtins__={})


_LOCATED = ("eval_all", "handle_macro_call", "process_include", "grab_property",
            "grab_macro")
"""Xacro functions that handle one element: an error inside is located at that element."""


@contextlib.contextmanager
def _locating(node: Any) -> Iterator[None]:
    """Tag an exception escaping the handling of `node` with where `node` was written
    (the innermost known element wins)."""
    try:
        yield
    except Exception as exc:
        if getattr(exc, "_urdfinertia_where", None) is None:
            where = getattr(node, "_urdfinertia_src", None)
            if where is None and node.nodeType == node.ELEMENT_NODE:
                where = _parse_location(node.getAttribute(SOURCE_ATTR))
            if where is not None:
                setattr(exc, "_urdfinertia_where", where)  # noqa: B010 - not our class
        raise


def _parse_location(text: str) -> tuple[int, int] | None:
    index, sep, offset = text.partition(":")
    return (int(index), int(offset)) if sep and index.isdigit() and offset.isdigit() else None


@contextlib.contextmanager
def _patched(state: _State) -> Iterator[None]:
    """xacro with the hooks in place; everything restored afterwards."""
    import xacro
    from xacro import substitution_args

    hooks = _hooks(state)
    saved = (substitution_args._eval_find, substitution_args._eval_dict["find"],
             xacro.verbosity)
    saved_functions = {name: getattr(xacro, name)
                       for name in (*_LOCATED, "parse", "safe_eval")}
    ns = xacro._global_symbols["xacro"]
    saved_yaml = (dict.get(ns, "load_yaml"), xacro._global_symbols.get("load_yaml"))
    for name in saved_functions:
        setattr(xacro, name, hooks[name])
    substitution_args._eval_find = hooks["find"]
    substitution_args._eval_dict["find"] = hooks["find"]
    dict.__setitem__(ns, "load_yaml", hooks["load_yaml"])
    xacro._global_symbols["load_yaml"] = hooks["load_yaml"]
    xacro.all_includes = []
    try:
        yield
    finally:
        for name, function in saved_functions.items():
            setattr(xacro, name, function)
        (substitution_args._eval_find, substitution_args._eval_dict["find"],
         xacro.verbosity) = saved
        dict.__setitem__(ns, "load_yaml", saved_yaml[0])
        xacro._global_symbols["load_yaml"] = saved_yaml[1]
        xacro.substitution_args_context["arg"] = {}
        xacro.all_includes = []


def expand_xacro(path: str | Path, data: bytes | None = None, *,
                 settings: XacroSettings | None = None,
                 overrides: Mapping[Path, bytes] | None = None) -> Expansion:
    """Expand the xacro file at `path` (its bytes `data` if given) to URDF.

    Raises `UrdfError` naming the xacro file and line of any xacro, YAML or XML
    error, a refused file (URL, entity declaration, size) or a package not found.
    """
    import xacro

    path = Path(path).absolute()
    settings = settings or current_settings()
    real = {os.path.realpath(p): v for p, v in (overrides or {}).items()}
    if data is not None:
        real.setdefault(os.path.realpath(path), data)
    state = _State(real, settings, path.parent, allowed_folders(path.parent, settings))
    warnings = io.StringIO()
    with _LOCK, _patched(state), contextlib.redirect_stderr(warnings):
        try:
            xacro.init_stacks(str(path))
            doc = xacro.parse(None, str(path))
            xacro.process_doc(doc, mappings=dict(settings.args), verbosity=0)
        except UrdfInertiaError as exc:
            raise _located(exc, state, exc, xacro) from None
        except RecursionError as exc:  # located at the innermost element it could tag
            raise _located(UrdfError("xacro: recursion too deep (an include or macro that "
                                     "includes or calls itself, or elements nested too "
                                     "deep?)"), state, exc, xacro) from None
        except Exception as exc:  # xacro raises many types; each becomes one located line
            inner = _inner_error(exc)
            if inner is not None:  # a hook's refusal, wrapped by xacro's expression handler
                raise _located(inner, state, exc, xacro) from None
            cause = " ".join(str(exc).split()) or type(exc).__name__
            raise _located(UrdfError(f"xacro: {cause}"), state, exc, xacro) from None
    locations = _strip_and_locate(doc)
    document = doc.toprettyxml(indent="  ", encoding="utf-8")
    doc.unlink()
    return Expansion(document, tuple(state.sources), tuple(state.source_bytes),
                     tuple(locations), warnings.getvalue())


def _inner_error(exc: BaseException) -> UrdfInertiaError | None:
    seen = 0
    current: BaseException | None = exc
    while current is not None and seen < 20:
        if isinstance(current, UrdfInertiaError):
            return current
        current = getattr(current, "exc", None) or current.__context__
        seen += 1
    return None


def _located(error: UrdfInertiaError, state: _State, exc: BaseException | None,
             xacro: Any) -> UrdfInertiaError:
    if error.file is not None:  # raised about a file of its own (a refused include)
        return error
    where = getattr(exc, "_urdfinertia_where", None) if exc is not None else None
    if where is not None and where[0] < len(state.sources):
        index, offset = where
        return error.with_context(file=state.sources[index],
                                  line=line_of(state.source_bytes[index], offset))
    stack = [f for f in (xacro.filestack or []) if f]
    return error.with_context(file=stack[-1] if stack else None)


def _strip_and_locate(doc: minidom.Document) -> list[tuple[int, int] | None]:
    """Remove the source tags and whitespace-only text; each element's source in order."""
    out: list[tuple[int, int] | None] = []
    root = doc.documentElement
    stack: list[minidom.Element] = [root] if root is not None else []
    while stack:
        node = stack.pop()
        out.append(_parse_location(node.getAttribute(SOURCE_ATTR)))
        if node.hasAttribute(SOURCE_ATTR):
            node.removeAttribute(SOURCE_ATTR)
        children = []
        for child in list(node.childNodes):
            if child.nodeType == child.TEXT_NODE and not child.data.strip():
                node.removeChild(child)
            elif child.nodeType == child.ELEMENT_NODE:
                children.append(child)
        stack.extend(reversed(children))
    return out
