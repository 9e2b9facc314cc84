"""WEB.TLM XML bodies: requests built, replies parsed by a hardened lxml parser.

A reply is refused whole (PlcProtocolError) when it is larger than MAX_REPLY, declares a DTD or
entities, refers to an entity, or is not a `<files>` document: nothing is loaded from a file or
the network, and no entity is expanded, whatever the reply says. Elements are known by their
local name (any namespace); attributes and children the client does not need are ignored,
except those whose name says an error (FAILURE) or, on an item without values, any at all.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
import re

from lxml import etree

from ...errors import PlcProtocolError

MAX_REPLY = 4 * 1024 * 1024
"""Bytes a reply may have. A 1,000-point poll answers about 20 KB, a whole 10,000-word file
about 70 KB: four megabytes is generous and still keeps a hostile reply small."""
_PARSER = etree.XMLParser(
    resolve_entities=False,
    no_network=True,
    load_dtd=False,
    dtd_validation=False,
    attribute_defaults=False,
    huge_tree=False,
    remove_comments=True,
    remove_pis=True,
    collect_ids=False,
)
_DECLARATION = re.compile(rb"<!(?!--|\[CDATA\[)")
FAILURE = re.compile(r"err|fault|fail", re.IGNORECASE)
"""Names of attributes or children that mark an item failed (the manual defines none)."""
"""A markup declaration (DOCTYPE, ENTITY, ELEMENT...): not comments or CDATA."""


@dataclass(frozen=True, slots=True)
class Item:
    """One `<data>` of a reply: what it names, the count it claims, its values or its error."""

    ad: str
    count: int | None
    tokens: tuple[str, ...]
    error: str = ""  # the PLC's words when the item says it failed (an error attribute or child)


def request_body(items: Iterable[tuple[str, int | None, str | None]]) -> bytes:
    """Return a `<files>` body of (ad, count, values) items; values None for a read."""
    root = etree.Element("files")
    for ad, count, values in items:
        data = etree.SubElement(root, "data", ad=ad)
        if count is not None:
            data.set("count", str(count))
        if values is not None:
            data.text = values
    return bytes(etree.tostring(root, xml_declaration=True, encoding="utf-8"))


def parse_reply(body: bytes) -> list[Item]:
    """Return the `<data>` items of a reply; raise PlcProtocolError for anything unsafe or odd."""
    root = _document(body)
    if _local(root) != "files":
        raise PlcProtocolError(f"the PLC answered a <{_name(root)}> document, not <files>")
    items: list[Item] = []
    for child in root:
        if not isinstance(child.tag, str):
            raise PlcProtocolError("the PLC's reply refers to an entity: refused")
        if _local(child) != "data":
            continue  # error documents and later additions: what the items lack says it
        items.append(_item(child))
    return items


def error_text(body: bytes, limit: int = 200) -> str:
    """Return what an error reply says, as plain text (markup dropped), cut short; never parsed."""
    text = body[: limit * 4].decode("utf-8", "replace")
    text = re.sub(r"<[^>]*>", " ", text)
    text = " ".join(text.split())
    return text[:limit]


def _document(body: bytes) -> etree._Element:
    """Parse a reply with the hardened parser, after the checks that keep it harmless."""
    if len(body) > MAX_REPLY:
        raise PlcProtocolError(f"the PLC's reply is larger than {MAX_REPLY} bytes: refused")
    if b"\x00" in body:  # also keeps out UTF-16 and UTF-32, where the next check sees nothing
        raise PlcProtocolError("the PLC's reply is not UTF-8 XML")
    if _DECLARATION.search(body):
        raise PlcProtocolError("the PLC's reply declares a DTD or entities: refused")
    try:
        root = etree.fromstring(body, _PARSER)
    except (etree.XMLSyntaxError, ValueError) as err:
        raise PlcProtocolError(f"the PLC's reply is not well-formed XML: {err}") from None
    if root is None:
        raise PlcProtocolError("the PLC's reply is empty")
    docinfo = root.getroottree().docinfo
    if (
        getattr(docinfo, "doctype", "")
        or docinfo.internalDTD is not None
        or docinfo.externalDTD is not None
    ):
        raise PlcProtocolError("the PLC's reply declares a DTD: refused")
    return root


def _item(data: etree._Element) -> Item:
    """Return one reply item; an error attribute or child marks it failed (see FAILURE)."""
    ad = data.get("ad")
    if ad is None:
        raise PlcProtocolError("the PLC's reply has a <data> without an ad")
    tokens = tuple((data.text or "").split())
    failed: list[str] = []
    other: list[str] = []
    for child in data:
        if not isinstance(child.tag, str):
            raise PlcProtocolError("the PLC's reply refers to an entity: refused")
        name = _local(child)
        words = " ".join(_text(part) for part in child.itertext()).strip() or name
        (failed if FAILURE.search(name) else other).append(words)
    for key, value in data.attrib.items():
        name = etree.QName(key).localname
        if name not in ("ad", "count"):
            (failed if FAILURE.search(name) else other).append(f"{name} {_text(value)}")
    error = " ".join(failed or ([] if tokens else other)).strip()
    raw_count = data.get("count")
    try:
        count = None if raw_count is None else int(raw_count)
    except ValueError:
        raise PlcProtocolError(
            f"{ad[:40]}: the PLC answered count {str(raw_count)[:20]!r}"
        ) from None
    return Item(str(ad), count, tokens, error)


def _text(part: str | bytes) -> str:
    """Return lxml text as str (the stubs allow bytes)."""
    return part.decode("utf-8", "replace") if isinstance(part, bytes) else part


def _local(element: etree._Element) -> str:
    """Return an element's tag without its namespace."""
    return etree.QName(element).localname


def _name(element: etree._Element) -> str:
    """Return an element's tag for a message (an entity or comment has none)."""
    return str(element.tag)[:40] if isinstance(element.tag, str) else "?"
