"""A pasted YAML text read as plain data only: scalars, lists and mappings, bounded, with lines.

No tag of any kind (`!!binary`, `!!python/...`, `!foo`, even `!!str`), no anchor or alias and no
merge key is taken; the text is bounded in size (refused before any parsing) and in depth
(refused at the first event past it, before any deep structure is built). The data is built
from the parser's events without YAML's constructor, and every key and list item keeps the
line it stands on, so that each later check can name its line. Parsing takes time on a large
text: `read_yaml` is blocking work, for an executor.
"""

from __future__ import annotations

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

    The `export_config` action's response (the file under a `yaml:` key, literal or folded)
    is taken as the file itself; lines then count in the pasted text.
    """
    check_size(text)
    read = _read(text, 0)
    inner = read.data.get(RESPONSE_KEY) if isinstance(read.data, dict) else None
    if isinstance(inner, _Block) and len(read.data) == 1:
        return _read(inner.text, inner.offset)
    if isinstance(read.data, dict):
        read.data = {k: v.value if isinstance(v, _Block) else v for k, v in read.data.items()}
    return read


@dataclass(frozen=True, slots=True)
class _Block:
    """A top-level text value: its value, and its source as a file (folded kept as written)."""

    value: str
    text: str
    offset: int


class _Collection:
    """A list or mapping being built: its data, its path, and the key awaiting its value."""

    __slots__ = ("data", "key", "path")

    def __init__(self, data: dict[str, Any] | list[Any], path: Path) -> None:
        """Start empty at a path."""
        self.data = data
        self.path = path
        self.key: str | None = None


def _read(text: str, offset: int) -> YamlText:
    """Return the data of one YAML text whose first line is line `offset` + 1 of the paste."""
    result = YamlText(None)
    stack: list[_Collection] = []
    documents = 0
    try:
        for event in yaml.parse(text, Loader=yaml.SafeLoader):
            line = int(event.start_mark.line) + 1 + offset
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
                if len(stack) == 1 and isinstance(value, str) and event.style in ("|", ">"):
                    value = _Block(value, _source(text, event), line)
                _place(result, stack, value, line)
    except yaml.YAMLError as err:
        mark = getattr(err, "problem_mark", None)
        line = int(mark.line) + 1 + offset if mark is not None else offset + 1
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


def _source(text: str, event: yaml.ScalarEvent) -> str:
    """Return a block scalar's lines as written, without its indicator line and indentation.

    A folded (`>`) block joins the lines of a file; read from the source they stay lines.
    """
    if event.style == "|":
        return str(event.value)
    body = text[event.start_mark.index : event.end_mark.index].split("\n", 1)
    return textwrap.dedent(body[1]) if len(body) > 1 else ""
