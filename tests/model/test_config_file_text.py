"""The configuration file itself: stable output, read back as written, refused on its field."""

from __future__ import annotations

from typing import Any

from homeassistant.config_entries import SOURCE_USER
from homeassistant.const import CONF_HOST, CONF_PASSWORD, CONF_PORT, CONF_USERNAME
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry
import yaml

from custom_components.plc_bridge.const import (
    CONF_FINGERPRINT,
    CONF_OPTIONS,
    CONF_TLS,
    CONF_VENDOR,
    DOMAIN,
)
from custom_components.plc_bridge.flows.config_file_flow import CONF_CONFIGURATION, PASTE
from custom_components.plc_bridge.model.config_file import (
    SECRETS,
    ConfigFileError,
    check_pasted,
    dump_config,
    load_config,
)
from custom_components.plc_bridge.model.vendor_fields import VENDOR_FIELDS
from custom_components.plc_bridge.plc.vendors import client_class
from tests.entries import POINTS, PointData, device, point
from tests.flows.forms import error_message, suggested, translated

pytestmark = pytest.mark.no_pacing

DATA = {
    CONF_VENDOR: "s7_smart",
    CONF_HOST: "192.0.2.10",
    CONF_PORT: 443,
    CONF_TLS: "pin",
    CONF_FINGERPRINT: "ab" * 32,
    CONF_USERNAME: "admin",
    CONF_PASSWORD: "Secret-Password-1",
    CONF_OPTIONS: {},
}


def plc(points: list[PointData] = POINTS, *, reverse: bool = False, **data: Any) -> MockConfigEntry:
    """Return a PLC's entry (not added) with two machines; `reverse`: stored the other way round."""
    step = -1 if reverse else 1
    machines = [
        device(points[::step], subentry_id="boiler", title="Boiler"),
        device(points[:2][::step], subentry_id="annex", title="Annex"),
    ]
    return MockConfigEntry(
        domain=DOMAIN,
        title="Boiler house",
        data=DATA | data,
        options={"scan_interval": 5.0},
        subentries_data=machines[::step],
        version=2,
    )


def test_dump_is_stable() -> None:
    """The same PLC gives the same text however it was stored; the points ordered by name."""
    text = dump_config(plc())
    assert dump_config(plc(reverse=True)) == text
    assert text.index("title: Annex") < text.index("title: Boiler\n")
    names = [
        line.split(": ", 1)[1] for line in text.splitlines() if line.startswith("        name:")
    ]
    boiler = names[2:]
    assert boiler == [
        "Clock",
        "Door",
        "Label",
        "Pressure",
        "Pump",
        "Raw",
        "Setpoint",
        "Temperature",
    ]


def test_load_gives_back_what_was_dumped() -> None:
    """Read back, the file is the entry less its password: and it dumps to the same text again."""
    entry = plc()
    pasted = load_config(dump_config(entry), version=2)
    assert pasted.data == {k: v for k, v in DATA.items() if k != CONF_PASSWORD}
    assert pasted.secrets == (CONF_PASSWORD,)
    assert (pasted.title, pasted.version, pasted.options) == (
        "Boiler house",
        2,
        {"scan_interval": 5.0},
    )
    stored = sorted(
        (s.subentry_type, s.title, s.unique_id, dict(s.data)) for s in entry.subentries.values()
    )
    read = sorted(
        (s["subentry_type"], s["title"], s["unique_id"], s["data"]) for s in pasted.subentries
    )
    assert read == stored
    again = MockConfigEntry(
        domain=DOMAIN,
        title=pasted.title,
        data=pasted.data,
        options=pasted.options,
        subentries_data=pasted.subentries,
        version=pasted.version,
    )
    assert dump_config(again) == dump_config(entry).replace("- password\n", "").replace(
        "secrets:\n", "secrets: []\n"
    )


def test_secrets_never_written() -> None:
    """Password and SoftPLC key material stay out; an empty password (no users) stays in."""
    material = {"client_certificate": "-----BEGIN CERTIFICATE-----\nAAAA", "client_key": "KEYKEY"}
    text = dump_config(plc(vendor="softplc", password="", vendor_options=material))
    document = yaml.safe_load(text)
    assert document["secrets"] == ["client_certificate", "client_key"]
    assert "AAAA" not in text
    assert "KEYKEY" not in text
    assert document["connection"][CONF_PASSWORD] == ""
    assert "Secret-Password-1" not in dump_config(plc())


def test_every_secret_field_is_left_out() -> None:
    """A connection field marked as a credential is on the list of secrets the file leaves out."""
    credentials = {f.key for fields in VENDOR_FIELDS.values() for f in fields if f.credential}
    assert credentials | {CONF_PASSWORD} <= set(SECRETS)


def edited(**changes: Any) -> str:
    """Return the file of the test PLC with top-level or connection keys changed."""
    document = yaml.safe_load(dump_config(plc()))
    for key, value in changes.items():
        if key in document["connection"]:
            document["connection"][key] = value
        else:
            document[key] = value
    return str(yaml.safe_dump(document))


BAD_ADDRESS = dump_config(plc()).replace("address: VD100", "address: VX100")
BAD_AVAILABILITY = dump_config(plc()).replace(
    "  title: Annex\n  unique_id: null\n  data:\n",
    "  title: Annex\n  unique_id: null\n  data:\n"
    "    availability_address: VX1\n    availability_data_type: signed\n",
    1,
)
ALIASES = dump_config(plc()).replace(
    "  title: Annex\n  unique_id: null\n  data:\n",
    "  title: Annex\n  unique_id: null\n  data:\n"
    "    spare: &a [0, 0, 0, 0, 0, 0, 0, 0, 0, 0]\n"
    "    more: &b [*a, *a, *a, *a, *a, *a, *a, *a, *a, *a]\n",
    1,
)
"""A few lines of YAML aliases stand for a tree no memory holds (here only a hundred leaves)."""


def line_of(text: str, part: str) -> int:
    """Return the number of the line of a text that holds a part."""
    return next(n for n, line in enumerate(text.splitlines(), 1) if part in line)


TEXT = dump_config(plc())
AS_DATETIME = TEXT.replace(
    "name: Pump\n        offset: 0.0\n        platform: switch",
    "name: Pump\n        offset: 0.0\n        platform: datetime",
)
SCALE_ZERO = TEXT.replace("scale: 0.1", "scale: 0.0", 1)
MIN_OVER_MAX = TEXT.replace("min: 10.0", "min: 70.0")
STOP_ONLY = dump_config(plc([point("stop", "Shutter", "cover", "Q0.1", "signed", role="stop")]))
"""Points every form and table refuses, each written into an otherwise exported file."""


async def pasted(hass: HomeAssistant, text: str) -> Any:
    """Paste a text on the config flow's paste page; return the result, its texts translated."""
    result = await hass.config_entries.flow.async_init(DOMAIN, context={"source": SOURCE_USER})
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {"next_step_id": PASTE}
    )
    return translated(
        await hass.config_entries.flow.async_configure(
            result["flow_id"], {CONF_CONFIGURATION: text}
        ),
        "config",
    )


@pytest.mark.parametrize(
    ("text", "on_line", "message"),
    [
        (AS_DATETIME, "platform: datetime", "A date and time entity needs a date/time point"),
        (SCALE_ZERO, "scale: 0.0", "the point Pressure cannot be used as it is: The scale"),
        (MIN_OVER_MAX, "max: 60.0", "The maximum must be greater than the minimum."),
        (STOP_ONLY, "stop:", "Shutter: give at least one of these parts: position"),
    ],
    ids=["platform", "scale", "range", "roles"],
)
async def test_refused_as_the_forms_refuse(
    hass: HomeAssistant, text: str, on_line: str, message: str
) -> None:
    """A point a form or table would refuse is refused in the file too, on its line."""
    result = await pasted(hass, text)
    assert result["type"] is FlowResultType.FORM
    shown = error_message(result, CONF_CONFIGURATION, "config")
    assert message in shown
    line = int(shown.removeprefix("Line ").split(":", 1)[0])
    assert on_line in text.splitlines()[line - 1]
    assert not hass.config_entries.async_entries(DOMAIN)


@pytest.mark.parametrize(
    ("text", "key", "message"),
    [
        ("plc_bridge: 1\ntitle: [Boiler\n", "config_malformed", "line 3"),
        ("title: Boiler house\n", "config_not_ours", "plc_bridge, is missing"),
        (edited(port="https"), "config_bad_value", "port must be whole number"),
        (edited(version=3), "config_newer", "newer release"),
        (edited(plc_bridge=2), "config_newer", "newer release"),
        (edited(vendor="modbus"), "config_unknown_vendor", "family modbus"),
        (
            BAD_ADDRESS,
            "config_bad_address",
            f"Line {line_of(BAD_ADDRESS, 'VX100')}: the point Temperature has an address",
        ),
        (
            BAD_AVAILABILITY,
            "config_bad_address",
            f"Line {line_of(BAD_AVAILABILITY, 'VX1')}: the point Annex has an address",
        ),
        (
            dump_config(plc()).replace("type: device", "type: sensor"),
            "config_bad_value",
            "type must be",
        ),
        (ALIASES, "config_alias", "line 24"),
    ],
    ids=[
        "yaml",
        "not ours",
        "port",
        "version",
        "format",
        "vendor",
        "address",
        "availability",
        "type",
        "aliases",
    ],
)
async def test_refused_on_the_field(hass: HomeAssistant, text: str, key: str, message: str) -> None:
    """A text that cannot become a PLC is refused on its field, said why; nothing is created."""
    result = await pasted(hass, text)
    assert result["type"] is FlowResultType.FORM
    assert (result["step_id"], result["errors"]) == (PASTE, {CONF_CONFIGURATION: key})
    assert message in error_message(result, CONF_CONFIGURATION, "config")
    assert suggested(result, CONF_CONFIGURATION) == text  # kept, to be corrected
    assert not hass.config_entries.async_entries(DOMAIN)


def test_bad_address_names_the_point() -> None:
    """The error names the point, its address and the parser's words."""
    with pytest.raises(ConfigFileError) as caught:
        check_pasted(client_class("s7_smart"), load_config(BAD_ADDRESS, version=2))
    assert caught.value.placeholders["point"] == "Temperature"
    assert caught.value.placeholders["address"] == "VX100"
    assert caught.value.placeholders["problem"]
