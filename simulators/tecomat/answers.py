"""The simulated PLC's GetObject answers: names nested as in 5.1, array elements in any shape."""

from __future__ import annotations

from typing import Any

from .program import Node, Segment, parse, positions, resolve, stopped_at
from .values import Fault, leaves, render


def place(answer: dict[str, Any], canonical: list[Segment], value: Any) -> None:
    """Put a value into a GetObject answer: members nest; "arr1[2]" keys an array element."""
    keys: list[str] = []
    for part in canonical:
        if isinstance(part, int):
            keys[-1] += f"[{part}]"
        else:
            keys.append(part)
    node = answer
    for key in keys[:-1]:
        node = node.setdefault(key, {})
    old = node.get(keys[-1])
    if isinstance(old, dict) and isinstance(value, dict):
        old.update(value)
    else:
        node[keys[-1]] = value


ARRAY_ANSWERS = ("keyed", "whole", "partial", "compact", "flat", "objects")
"""How a PLC may answer elements of an array; the spec shows whole arrays only (5.2).

keyed: `{"arr2[1][3]": v}`; whole: the whole array, as if it were asked; partial: nested arrays
padded with null up to the highest asked element (positions from the array's first element);
compact: nested arrays of the asked elements
only, in index order; flat: one array of the asked elements, in request order; objects: objects
keyed by index, `{"arr2": {"1": {"3": v}}}`.
"""


ELEMENT_SPELLINGS = ("any", "brackets", "comma")
"""How a request may name an element of several indices (5.2 shows none): any, only arr2[1][3],
or only arr2[1,3] (IEC 61131-3); the other spelling is an unknown variable (400.005)."""


def _spelled_as(name: str, spelling: str) -> bool:
    """True when the PLC takes a name's element spelling."""
    if spelling == "brackets":
        return "," not in name
    return spelling != "comma" or "][" not in name


def read(
    variables: dict[str, Node],
    names: list[str],
    limit: int,
    *,
    leaf_names: bool = False,
    array_answers: str = "keyed",
    asked_case: bool = False,
    element_spelling: str = "any",
    whole_arrays: str = "list",
) -> dict[str, Any]:
    """Answer GetObject; the first unknown name fails the request (400.005).

    With `leaf_names` the error names only the item where the walk stopped, not the path.
    `array_answers` picks how elements of an array come (ARRAY_ANSWERS). With `asked_case` the
    answer spells names as the request did, else as the program declares them.
    `element_spelling` is how the PLC takes an element of several indices (ELEMENT_SPELLINGS).
    `whole_arrays` is how an array read whole comes (values.WHOLE_ARRAYS); `partial` and
    `compact` lists hold elements by position from the array's first element.
    """
    answer: dict[str, Any] = {}
    elements: dict[tuple[str, ...], Any] = {}
    items = 0
    for name in names:
        parts = parse(name) if _spelled_as(name, element_spelling) else None
        try:
            if parts is None:
                raise KeyError(name)
            canonical, node = resolve(variables, parts)
        except KeyError:
            shown = stopped_at(variables, parts) if parts and leaf_names else name
            raise Fault("400.005", f"Variable '{shown}' is not found") from None
        items += leaves(node)
        placed = positions(variables, canonical)
        if asked_case:
            canonical = parts
        first = next((at for at, part in enumerate(canonical) if isinstance(part, int)), 0)
        value = render(node, whole_arrays)
        if not first or array_answers == "keyed":
            place(answer, canonical, value)
            continue
        root = tuple(str(part) for part in canonical[:first])
        if array_answers == "whole":
            place(answer, list(root), render(resolve(variables, list(root))[1], whole_arrays))
        elif array_answers == "flat":
            elements.setdefault(root, []).append(value)
        else:
            rest = canonical[first:] if array_answers == "objects" else placed[first:]
            elements[root] = _put(elements.get(root), rest, value)
    if items > limit:
        raise Fault("413.004", f"Too many variables (maximum is {limit})")
    for root, tree in elements.items():
        place(answer, list(root), tree if array_answers == "flat" else _shaped(tree, array_answers))
    return answer


def _put(tree: Any, rest: list[Segment], value: Any) -> Any:
    """Put a value at rest below tree (dicts keyed by names and indices, made as needed)."""
    if not rest:
        return value
    tree = tree if isinstance(tree, dict) else {}
    tree[rest[0]] = _put(tree.get(rest[0]), rest[1:], value)
    return tree


def _shaped(tree: Any, shape: str) -> Any:
    """Return a tree of asked elements as `partial`, `compact` or `objects` answers them."""
    if not isinstance(tree, dict) or not tree:
        return tree
    if not all(isinstance(key, int) for key in tree):
        return {key: _shaped(value, shape) for key, value in tree.items()}
    if shape == "objects":
        return {str(key): _shaped(value, shape) for key, value in tree.items()}
    if shape == "compact":
        return [_shaped(tree[key], shape) for key in sorted(tree)]
    padded: list[Any] = [None] * (max(tree) + 1)
    for key, value in tree.items():
        padded[key] = _shaped(value, shape)
    return padded
