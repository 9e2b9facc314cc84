"""SoftPLC edges: ranges split around a refused element, odd replies, the link going away."""

from __future__ import annotations

import re
from typing import TYPE_CHECKING

from aiohttp import web
import pytest

from custom_components.plc_bridge.plc import (
    PlcAddressError,
    PlcConnectionError,
    PlcProtocolError,
    PlcValueError,
    PlcWriteRefusedError,
    Point,
)
from custom_components.plc_bridge.plc.vendors.softplc import SoftplcClient
from custom_components.plc_bridge.plc.vendors.softplc.codec import (
    decode,
    parse_token,
    same_float,
    word_of,
)
from custom_components.plc_bridge.plc.vendors.softplc.document import parse_reply
from custom_components.plc_bridge.plc.vendors.softplc.tls import MaterialError, pem_options
from simulators.softplc import SoftplcSimulator

if TYPE_CHECKING:
    from .softplc_fixtures import ConfigFactory


async def test_range_split_around_a_refused_element(
    softplc_sim: SoftplcSimulator, softplc_client: SoftplcClient
) -> None:
    """A merged range the PLC refuses (count past the end is an error here) is asked again
    element by element: the element that exists reads, the one past the end fails alone."""
    softplc_sim.past_end = "error"
    inside, beyond = Point("N7:98", "INT"), Point("N7:101", "INT")
    values = (await softplc_client.read([inside, beyond])).values
    assert values[inside].value == 98
    assert isinstance(values[beyond].error, PlcAddressError)
    # the range; its two elements; refused together (bad_item "request"), so one by one
    assert list(softplc_sim.items) == [1, 2, 1, 1]


async def test_points_that_cannot_be_asked(softplc_client: SoftplcClient) -> None:
    """An address that does not parse fails alone, without a request; planning skips it."""
    bad, good = Point("N7:x", "INT"), Point("N7:1", "INT")
    values = (await softplc_client.read([bad, good])).values
    assert isinstance(values[bad].error, PlcAddressError)
    assert values[good].value == 1
    assert SoftplcClient.items_for([bad, good]) == 1
    assert SoftplcClient.value_kind(bad) is None


@pytest.mark.parametrize(
    ("pattern", "replacement", "error"),
    [
        (rb'<data ad="N7:1" count="1">', b'<data ad="N7:1" count="2">', PlcProtocolError),
        (rb"\n1\n", b"\nabc\n", PlcProtocolError),
        (rb"\n1\n", b"\n1.5\n", PlcProtocolError),
        (rb"\n1\n", b"\n70000\n", PlcProtocolError),
        (rb'<data ad="N7:1" count="1">\n1\n</data>', b"", PlcProtocolError),
    ],
)
async def test_odd_values_fail_their_point(
    softplc_sim: SoftplcSimulator,
    softplc_client: SoftplcClient,
    pattern: bytes,
    replacement: bytes,
    error: type[Exception],
) -> None:
    """A count that disagrees, a token that is no word, or a missing item fails that point."""
    softplc_sim.rewrite = lambda body: re.sub(pattern, replacement, body)
    one, other = Point("N7:1", "INT"), Point("F8:0", "REAL")
    values = (await softplc_client.read([one, other])).values
    assert isinstance(values[one].error, error)
    assert values[other].value == 21.5


async def test_set_bit_of_a_word_the_plc_refuses(
    softplc_sim: SoftplcSimulator, softplc_client: SoftplcClient
) -> None:
    """A bit is written through its word: a word that cannot be read fails that bit alone."""
    bad, good = Point("B3:99/1", "BOOL"), Point("B3:0/2", "BOOL")
    results = await softplc_client.write({bad: True, good: True})
    assert isinstance(results[bad].error, PlcWriteRefusedError)
    assert results[good].value is True
    assert softplc_sim.files["B", 3].words[0] & 0b100


async def test_written_value_unreadable(
    softplc_sim: SoftplcSimulator, softplc_client: SoftplcClient
) -> None:
    """A write the PLC answered (2xx, its item without an error) with no number, or without
    the value, is done: reported written, not failed (READINGS.md row 15)."""
    softplc_sim.rewrite = lambda body: body.replace(b"\n77\n", b"\nbusy\n")
    point = Point("N7:0", "INT")
    assert (await softplc_client.write({point: 77}))[point].value == 77
    softplc_sim.rewrite = lambda body: body.replace(b"\n78\n", b"\n\n")
    assert (await softplc_client.write({point: 78}))[point].value == 78
    assert softplc_sim.files["N", 7].words[0] == 78


async def test_no_clock(softplc_client: SoftplcClient) -> None:
    """WEB.TLM serves the datatable only."""
    assert not softplc_client.can_set_clock
    with pytest.raises(PlcProtocolError):
        await softplc_client.read_clock()
    with pytest.raises(PlcWriteRefusedError):
        await softplc_client.set_clock(None)  # type: ignore[arg-type]


async def test_not_a_softplc(softplc_settings: ConfigFactory) -> None:
    """A web server without /dt is no WEB.TLM."""
    runner = web.AppRunner(web.Application())
    await runner.setup()
    site = web.TCPSite(runner, "127.0.0.1", 0)
    await site.start()
    port = site._server.sockets[0].getsockname()[1]  # type: ignore[union-attr]
    sim = SoftplcSimulator()
    sim.host, sim.port = "127.0.0.1", port
    client = SoftplcClient(softplc_settings(sim))
    try:
        with pytest.raises(PlcProtocolError, match="HTTP 404"):
            await client.connect()
    finally:
        await client.close()
        await runner.cleanup()


async def test_plc_gone_with_a_certificate(softplc_settings: ConfigFactory) -> None:
    """With a certificate, a PLC that does not answer at all is a link error, not a refusal."""
    sim = SoftplcSimulator(tls=True, put_auth=True, bench=0)
    await sim.start()
    certificate, key = sim.client_certificate()
    options = SoftplcClient.validate_options({"client_certificate": certificate, "client_key": key})
    client = SoftplcClient(softplc_settings(sim, options=options, tls="off"))
    await sim.stop()
    try:
        with pytest.raises(PlcConnectionError):
            await client.connect()
        with pytest.raises(PlcConnectionError):
            await client.check_certificate()
    finally:
        await client.close()


def test_codec_edges() -> None:
    """Tokens and words the codec refuses, and floats past a single's range."""
    with pytest.raises(PlcProtocolError):
        parse_token("12abc", "N7:0")
    with pytest.raises(PlcProtocolError):
        decode("INT", 1.5, None, "N7:0")
    assert decode("UINT", 7.0, None, "N7:0") == 7
    with pytest.raises(PlcValueError):
        word_of("INT", 1.5)
    assert not same_float(1e300, 1.0)


def test_document_edges() -> None:
    """Other elements are skipped; a <data> without ad, or a PI-free oddity, is refused."""
    body = b'<?xml version="1.0"?><files><error>x</error><data ad="N7:0" count="1">4</data></files>'
    assert [item.ad for item in parse_reply(body)] == ["N7:0"]
    with pytest.raises(PlcProtocolError, match="without an ad"):
        parse_reply(b"<files><data>4</data></files>")
    with pytest.raises(PlcProtocolError, match="larger than"):
        parse_reply(b"<files>" + b" " * (4 * 1024 * 1024) + b"</files>")


@pytest.mark.parametrize(
    ("options", "option"),
    [
        ({"client_certificate": 5, "client_key": "x"}, "client_certificate"),
        ({"client_key": "-----BEGIN PRIVATE KEY-----"}, "client_certificate"),
        ({"client_certificate": "/c.pem"}, "client_key"),
    ],
)
def test_material_blamed_on_its_option(options: dict[str, object], option: str) -> None:
    """The option at fault is named, for the form to show the error on its field."""
    with pytest.raises(MaterialError) as raised:
        pem_options(options)
    assert raised.value.option == option


def test_attributes_not_needed_are_ignored() -> None:
    """Extra attributes (namespaced or not) and namespaced elements do not fail an item; an
    attribute or child whose name says an error does; so does any child of an item with no
    values."""
    body = (
        b'<files xmlns="urn:a" xmlns:w="urn:w"><data ad="N7:0" count="1" w:scan="5" q="good">'
        b'4</data><data ad="N7:1" count="1" w:errorCode="7"/><data ad="N7:2" count="1">'
        b'<message>no such file</message></data><data ad="N7:3">5<w:stamp>1</w:stamp></data>'
        b"</files>"
    )
    items = parse_reply(body)
    assert [(item.tokens, item.error) for item in items] == [
        (("4",), ""),
        ((), "errorCode 7"),
        ((), "no such file"),
        (("5",), ""),
    ]
