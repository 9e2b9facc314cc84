"""A pasted YAML text read as plain data only: scalars, lists and mappings, bounded, with lines.

No tag of any kind (`!!binary`, `!!python/...`, `!foo`, even `!!str`), no anchor or alias and no
merge key is taken; the text is bounded in size (refused before any parsing) and in depth
(refused at the first event past it, before any deep structure is built). The data is built
from the parser's events without YAML's constructor, and every key and list item keeps the
line it stands on, so that each later check can name its line. Parsing takes time on a large
text: `read_yaml` is blocking work, for an executor.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
import math
import textwrap
from typing import Any

import yaml
from yaml.constructor import SafeConstructor
from yaml.nodes import ScalarNode
from yaml.resolver import Resolver

MAX_BYTES = 256 * 1024
"""The largest text taken (an export of a PLC of thousands of points is far smaller)."""
MAX_DEPTH = 20
"""The deepest nesting of lists and mappings taken (an export nests five levels)."""
RESPONSE_KEY = "yaml"
"""The key under which the `export_config` action's response holds the file."""

type Path = tuple[str | int, ...]
"""Where a value stands: the keys and list indexes from the top."""

_TYPES = {
    "tag:yaml.org,2002:null": "null",
    "tag:yaml.org,2002:bool": "bool",
    "tag:yaml.org,2002:int": "int",
    "tag:yaml.org,2002:float": "float",
}
_RESOLVER = Resolver()
_CONSTRUCTOR = SafeConstructor()


class YamlTextError(Exception):
    """A text that is not plain YAML data: a config flow error key and its placeholders."""

    def __init__(self, key: str, **placeholders: str) -> None:
        """Keep the error key and what its message names."""
        super().__init__(key, placeholders)
        self.key = key
        self.placeholders = placeholders


@dataclass(slots=True)
class YamlText:
    """Plain data read from a text, and the line (1-based) of each key and list item."""

    data: Any
    lines: dict[Path, int] = field(default_factory=dict)

    def line(self, path: Path) -> int:
        """Return the line of a path, or of the nearest enclosing one that has a line."""
        while path and path not in self.lines:
            path = path[:-1]
        return self.lines.get(path, 1)


def check_size(text: str) -> None:
    """Raise YamlTextError for a text over MAX_BYTES (cheap: no parsing, for the event loop)."""
    if len(text) > MAX_BYTES or len(text.encode()) > MAX_BYTES:
        raise YamlTextError("config_too_large", limit=f"{MAX_BYTES // 1024}")


def read_yaml(text: str) -> YamlText:
    """Return the text's plain data (blocking); raise YamlTextError on what is not plain.

    The `export_config` action's response (the file under a `yaml:` key, literal `|` or folded
    `>` with its long lines wrapped, as the action's response view shows it) is taken as the
    file itself, and so is the body of that block copied without its `yaml:` line; lines then
    count in the pasted text.
    """
    check_size(text)
    body = textwrap.dedent(text)
    if body == text or not body.strip():
        return _file(text, _shifted(0))
    try:
        return _file(body, _shifted(0))  # a literal block's body: the file, indented
    except YamlTextError as err:
        literal = err
    try:  # a folded block's body: its lines wrapped, a blank line between the file's lines
        return _file(f"{RESPONSE_KEY}: >\n{text}", _shifted(-1))
    except YamlTextError as err:
        # the reading that went further tells the problem
        if int(err.placeholders.get("line", 0)) > int(literal.placeholders.get("line", 0)):
            raise
        raise literal from None


type LineOf = Callable[[int], int]
"""The pasted line (1-based) of a line (0-based) of the text being read."""


def _shifted(offset: int) -> LineOf:
    """Return where the lines of a text are in the paste when it starts `offset` lines later."""
    return lambda index: index + 1 + offset


def _file(text: str, line_of: LineOf) -> YamlText:
    """Return a file's data, or that of the file an action response holds under `yaml:`."""
    read = _read(text, line_of)
    inner = read.data.get(RESPONSE_KEY) if isinstance(read.data, dict) else None
    if isinstance(inner, _Text) and len(read.data) == 1:
        read = _read(inner.value, inner.line_of)
    if isinstance(read.data, dict):
        read.data = {k: v.value if isinstance(v, _Text) else v for k, v in read.data.items()}
    return read


@dataclass(frozen=True, slots=True)
class _Text:
    """A top-level text value, and where each of its lines stands in the paste."""

    value: str
    line_of: LineOf


class _Collection:
    """A list or mapping being built: its data, its path, and the key awaiting its value."""

    __slots__ = ("data", "key", "path")

    def __init__(self, data: dict[str, Any] | list[Any], path: Path) -> None:
        """Start empty at a path."""
        self.data = data
        self.path = path
        self.key: str | None = None


def _read(text: str, line_of: LineOf) -> YamlText:
    """Return the data of one YAML text whose lines stand in the paste where `line_of` says."""
    result = YamlText(None)
    stack: list[_Collection] = []
    documents = 0
    try:
        for event in yaml.parse(text, Loader=yaml.SafeLoader):
            line = line_of(int(event.start_mark.line))
            if isinstance(event, yaml.AliasEvent) or getattr(event, "anchor", None):
                raise YamlTextError("config_alias", line=str(line))
            if getattr(event, "tag", None) is not None:
                raise YamlTextError("config_tag", line=str(line), tag=str(event.tag))
            if isinstance(event, yaml.DocumentStartEvent):
                documents += 1
                if documents > 1:
                    raise YamlTextError("config_documents", line=str(line))
            elif isinstance(event, yaml.MappingStartEvent | yaml.SequenceStartEvent):
                if len(stack) >= MAX_DEPTH:
                    raise YamlTextError("config_too_deep", line=str(line), depth=str(MAX_DEPTH))
                empty: dict[str, Any] | list[Any] = (
                    {} if isinstance(event, yaml.MappingStartEvent) else []
                )
                path = _place(result, stack, empty, line)
                stack.append(_Collection(empty, path))
            elif isinstance(event, yaml.MappingEndEvent | yaml.SequenceEndEvent):
                stack.pop()
            elif isinstance(event, yaml.ScalarEvent):
                top = stack[-1] if stack else None
                if top is not None and isinstance(top.data, dict) and top.key is None:
                    _key(result, top, event, line)
                    continue
                value = _scalar(event, line)
                if len(stack) == 1 and isinstance(value, str):
                    value = _Text(value, _value_lines(text, event, value, line_of))
                _place(result, stack, value, line)
    except yaml.YAMLError as err:
        mark = getattr(err, "problem_mark", None)
        line = line_of(int(mark.line) if mark is not None else 0)
        raise YamlTextError("config_malformed", line=str(line)) from err
    return result


def _key(result: YamlText, top: _Collection, event: yaml.ScalarEvent, line: int) -> None:
    """Take a mapping's key: its text, never twice, never YAML's merge key."""
    key = str(event.value)
    if event.implicit[0] and key == "<<":
        raise YamlTextError("config_alias", line=str(line))
    assert isinstance(top.data, dict)
    if key in top.data:
        raise YamlTextError("config_repeated_key", line=str(line), name=key)
    top.key = key
    result.lines[(*top.path, key)] = line


def _place(result: YamlText, stack: list[_Collection], value: Any, line: int) -> Path:
    """Put a value into the collection being built (or make it the document); return its path."""
    if not stack:
        result.data = value
        return ()
    top = stack[-1]
    if isinstance(top.data, list):
        path: Path = (*top.path, len(top.data))
        top.data.append(value)
        result.lines[path] = line
        return path
    if top.key is None:  # a list or mapping as a key
        raise YamlTextError("config_malformed", line=str(line))
    path = (*top.path, top.key)
    top.data[top.key] = value
    top.key = None
    return path


def _scalar(event: yaml.ScalarEvent, line: int) -> Any:
    """Return a scalar as plain YAML reads it: null, bool, int, finite float, else its text."""
    if not event.implicit[0]:  # quoted or block: text
        return str(event.value)
    tag = _RESOLVER.resolve(ScalarNode, event.value, (True, False))
    kind = _TYPES.get(tag)
    if kind is None:  # text, and what only a tag would make more of (timestamps)
        return str(event.value)
    node = ScalarNode(tag, event.value)
    value: Any = getattr(_CONSTRUCTOR, f"construct_yaml_{kind}")(node)
    if isinstance(value, float) and not math.isfinite(value):
        raise YamlTextError("config_not_finite", line=str(line), value=str(event.value))
    return value


def _value_lines(text: str, event: yaml.ScalarEvent, value: str, line_of: LineOf) -> LineOf:
    """Return where each line of a top-level text value stands in the paste.

    A literal block's lines follow its indicator one to one; a folded block's line starts at
    the first line of the block it begins with (its wrapped rest and the blank lines that keep
    line breaks follow); a quoted or plain text is all on its first line.
    """
    first = int(event.start_mark.line)
    if event.style == "|":
        return lambda index: line_of(first + 1 + index)
    if event.style != ">":
        return lambda index: line_of(first)
    source = text[event.start_mark.index : event.end_mark.index].split("\n")[1:]
    indent = min((len(s) - len(s.lstrip(" ")) for s in source if s.strip()), default=0)
    starts: list[int] = []
    at = 0
    for line in value.split("\n"):
        found = next(
            (
                j
                for j in range(at, len(source))
                if line and source[j].strip() and line.startswith(source[j][indent:])
            ),
            None,
        )
        at = at if found is None else found
        starts.append(first + 1 + at)
        at += found is not None
    return lambda index: line_of(starts[min(index, len(starts) - 1)] if starts else first)
