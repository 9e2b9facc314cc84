"""Hostile replies: a DOCTYPE, external entities, nested entities, oversized bodies.

Each is a PlcProtocolError for the whole poll, and nothing is read from a file or fetched.
The hardened parser is also tried alone (without the checks before it): it resolves nothing.
"""

from __future__ import annotations

from collections.abc import AsyncGenerator, Callable
from pathlib import Path

from aiohttp import web
from lxml import etree
import pytest

from custom_components.plc_bridge.plc import PlcProtocolError, Point
from custom_components.plc_bridge.plc.vendors.softplc import SoftplcClient, document
from simulators.softplc import SoftplcSimulator

SECRET = "TOP-SECRET-7f3a"


@pytest.fixture
async def web_server() -> AsyncGenerator[tuple[str, list[str]]]:
    """A web server on loopback that records every path asked of it."""
    hits: list[str] = []

    async def handle(request: web.Request) -> web.Response:
        hits.append(request.path)
        return web.Response(text=SECRET)

    app = web.Application()
    app.router.add_get("/{tail:.*}", handle)
    runner = web.AppRunner(app)
    await runner.setup()
    site = web.TCPSite(runner, "127.0.0.1", 0)
    await site.start()
    port = site._server.sockets[0].getsockname()[1]  # type: ignore[union-attr]
    yield f"http://127.0.0.1:{port}", hits
    await runner.cleanup()


def hostile(secret_file: Path, url: str) -> dict[str, bytes]:
    """Return the hostile replies, by name."""
    laughs = "".join(
        f'<!ENTITY l{i} "{f"&l{i - 1};" * 10}">' if i else '<!ENTITY l0 "lol">' for i in range(10)
    )
    return {
        "doctype": b'<?xml version="1.0"?><!DOCTYPE files><files><data ad="N7:0">1</data></files>',
        "file_entity": (
            f'<?xml version="1.0"?><!DOCTYPE files [<!ENTITY x SYSTEM "file://{secret_file}">]>'
            '<files><data ad="N7:0" count="1">&x;</data></files>'
        ).encode(),
        "network_entity": (
            f'<?xml version="1.0"?><!DOCTYPE files [<!ENTITY x SYSTEM "{url}/entity">]>'
            '<files><data ad="N7:0" count="1">&x;</data></files>'
        ).encode(),
        "external_dtd": (
            f'<?xml version="1.0"?><!DOCTYPE files SYSTEM "{url}/dtd">'
            '<files><data ad="N7:0" count="1">1</data></files>'
        ).encode(),
        "billion_laughs": (
            f'<?xml version="1.0"?><!DOCTYPE files [{laughs}]>'
            '<files><data ad="N7:0" count="1">&l9;</data></files>'
        ).encode(),
        "undeclared_entity": b'<files><data ad="N7:0" count="1">&x;</data></files>',
        "utf16_doctype": (
            '<?xml version="1.0" encoding="UTF-16"?><!DOCTYPE files [<!ENTITY x "1">]>'
            '<files><data ad="N7:0" count="1">&x;</data></files>'
        ).encode("utf-16"),
        "oversized": b"<files>" + b" " * (document.MAX_REPLY + 1) + b"</files>",
        "not_xml": b"<files><data ad='N7:0'>1</files>",
        "other_root": b'<response><data ad="N7:0" count="1">1</data></response>',
    }


@pytest.mark.parametrize(
    "case",
    [
        "doctype",
        "file_entity",
        "network_entity",
        "external_dtd",
        "billion_laughs",
        "undeclared_entity",
        "utf16_doctype",
        "oversized",
        "not_xml",
        "other_root",
    ],
)
async def test_hostile_reply_refused(
    softplc_client: SoftplcClient,
    softplc_sim: SoftplcSimulator,
    web_server: tuple[str, list[str]],
    tmp_path: Path,
    case: str,
) -> None:
    """The poll fails as a protocol error; no file is read and nothing is fetched."""
    secret_file = tmp_path / "secret.txt"
    secret_file.write_text(SECRET)
    url, hits = web_server
    body = hostile(secret_file, url)[case]
    softplc_sim.rewrite = lambda _body: body
    with pytest.raises(PlcProtocolError) as raised:
        await softplc_client.read([Point("N7:0", "")])
    assert SECRET not in str(raised.value)
    assert hits == []


@pytest.mark.parametrize("case", ["file_entity", "network_entity", "external_dtd"])
def test_parser_alone_resolves_nothing(
    web_server: tuple[str, list[str]], tmp_path: Path, case: str
) -> None:
    """Even without the checks before it, the parser neither reads the file nor fetches."""
    secret_file = tmp_path / "secret.txt"
    secret_file.write_text(SECRET)
    url, hits = web_server
    body = hostile(secret_file, url)[case]
    try:
        root = etree.fromstring(body, document._PARSER)
    except etree.XMLSyntaxError:  # "Attempt to load network entity": refused
        pass
    else:
        assert SECRET not in etree.tostring(root).decode()
    assert hits == []


def test_parser_alone_does_not_expand_laughs(tmp_path: Path) -> None:
    """Nested entities stay unexpanded references in the hardened parser."""
    body = hostile(tmp_path / "none", "http://127.0.0.1:9")["billion_laughs"]
    try:
        root = etree.fromstring(body, document._PARSER)
    except etree.XMLSyntaxError:
        return  # libxml2 refusing the amplification is as good
    assert len(etree.tostring(root)) < 10_000


@pytest.mark.parametrize(
    "make", [lambda: document.parse_reply(b"\x00<files/>"), lambda: document.parse_reply(b"")]
)
def test_decoder_refusals(make: Callable[[], object]) -> None:
    """NUL bytes and empty bodies are protocol errors."""
    with pytest.raises(PlcProtocolError):
        make()
