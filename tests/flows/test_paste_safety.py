"""A pasted PLC file is safe by construction: each case of issue 24 refused on its line.

Plain YAML only (no tag of any kind, no alias), bounded in size and depth; keys the model does
not know and values of the wrong kind refused on their line; the options form's floors and the
configuration folder's rule apply; nothing reaches the PLC or the stored entry.
"""

from __future__ import annotations

from typing import Any

from freezegun.api import FrozenDateTimeFactory
from homeassistant.config_entries import SOURCE_RECONFIGURE, SOURCE_USER
from homeassistant.const import CONF_PASSWORD
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
from homeassistant.helpers import entity_registry as er
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry
import yaml

from custom_components.plc_bridge.const import DOMAIN, SUBENTRY_EXPOSE
from custom_components.plc_bridge.flows.config_file_flow import CONF_CONFIGURATION, PASTE
from custom_components.plc_bridge.model.config_file import dump_config
from custom_components.plc_bridge.model.expose import CONF_SEND
from custom_components.plc_bridge.model.yaml_text import MAX_BYTES
from simulators.s7_smart import DEFAULT_PASSWORD as SMART_PASSWORD, S7SmartSimulator
from tests.entries import POINTS, device, point, sim_data
from tests.flows.forms import error_message, suggested, translated
from tests.harness import expose_data, settle
from tests.model.test_config_file_text import plc
from tests.test_config_file import CONFIG, confirm, paste

pytestmark = pytest.mark.no_pacing


def line_of(text: str, needle: str) -> str:
    """Return the line (1-based, as text) of the first line holding the needle."""
    return str(next(n for n, line in enumerate(text.splitlines(), 1) if needle in line))


def with_line(text: str, after: str, added: str) -> str:
    """Return the text with a line added after the first line holding `after`, its indent kept."""
    lines = text.splitlines(keepends=True)
    at = next(n for n, line in enumerate(lines) if after in line)
    indent = lines[at][: len(lines[at]) - len(lines[at].lstrip())]
    if lines[at].rstrip().endswith(":"):
        indent += "  "
    lines.insert(at + 1, f"{indent}{added}\n")
    return "".join(lines)


async def refused(hass: HomeAssistant, text: str) -> tuple[str, str]:
    """Paste the text; return the error key and message on the field; nothing is created."""
    result = await hass.config_entries.flow.async_init(DOMAIN, context={"source": SOURCE_USER})
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {"next_step_id": PASTE}
    )
    result = translated(
        await hass.config_entries.flow.async_configure(
            result["flow_id"], {CONF_CONFIGURATION: text}
        ),
        *CONFIG,
    )
    assert (result["type"], result["step_id"]) == (FlowResultType.FORM, PASTE)
    assert suggested(result, CONF_CONFIGURATION) == text
    assert not hass.config_entries.async_entries(DOMAIN)
    key = result["errors"][CONF_CONFIGURATION]
    return key, error_message(result, CONF_CONFIGURATION, *CONFIG)


pytestmark = pytest.mark.no_pacing  # an S7-200 SMART under the frozen clock

FILE = dump_config(plc())
TAGS = {
    "binary": "name: !!binary aGVsbG8=",
    "python": "name: !!python/object/apply:os.system ['true']",
    "local": "name: !foo Pressure",
    "str": "name: !!str Pressure",
}


@pytest.mark.parametrize("tagged", TAGS.values(), ids=TAGS.keys())
async def test_tags_refused_on_their_line(hass: HomeAssistant, tagged: str) -> None:
    """No tag of any kind: a `!!binary` value would keep Home Assistant from saving entries."""
    text = FILE.replace("name: Pressure", tagged)
    key, message = await refused(hass, text)
    assert key == "config_tag"
    assert message.startswith(f"Line {line_of(text, tagged)}:")


UNKNOWN = {
    "mac": ("host: 192.0.2.10", "mac: 00:1b:1b:aa:bb:cc"),
    "vendor option": ("vendor_options:", "debug: true"),
    "option": ("scan_interval:", "burst: 1"),
    "subentry": ("title: Annex", "owner: me"),
    "machine": ("  data:", "firmware: 2"),
    "point": ("name: Pressure", "script: rm"),
}


@pytest.mark.parametrize(("after", "added"), UNKNOWN.values(), ids=UNKNOWN.keys())
async def test_unknown_keys_refused_on_their_line(
    hass: HomeAssistant, after: str, added: str
) -> None:
    """A key the forms never store is refused on its line (a `mac` would move the entry)."""
    text = with_line(FILE.replace("vendor_options: {}", "vendor_options:"), after, added)
    if after != "vendor_options:":
        text = with_line(FILE, after, added)
    key, message = await refused(hass, text)
    assert key == "config_unknown_key"
    name = added.split(":", 1)[0]
    assert message.startswith(
        f"Line {line_of(text, added)}: PLC Bridge does not know the key {name}"
    )


async def test_unknown_key_of_an_expose(hass: HomeAssistant) -> None:
    """Every subentry type: an expose's unknown key too."""
    entry = plc()
    text = _with_expose(entry, expose_data("sensor.outdoor", ("VD400", "float")) | {"x": 1})
    key, message = await refused(hass, text)
    assert key == "config_unknown_key"
    assert message.startswith(f"Line {line_of(text, 'x: 1')}:")


def _with_expose(entry: MockConfigEntry, data: dict[str, Any]) -> str:
    """Return the entry's file with an expose subentry holding the data added."""
    document = yaml.safe_load(dump_config(entry))
    document["subentries"].append(
        {"type": SUBENTRY_EXPOSE, "title": "Sent", "unique_id": None, "data": data}
    )
    return str(yaml.safe_dump(document, sort_keys=False))


async def test_type_refused_on_its_line(hass: HomeAssistant) -> None:
    """A string where a number belongs is refused on its line."""
    text = FILE.replace("scale: 0.1", "scale: tenth")
    key, message = await refused(hass, text)
    assert key == "config_bad_value"
    assert message == f"Line {line_of(text, 'scale: tenth')}: scale must be number."


async def test_poll_interval_floor(hass: HomeAssistant) -> None:
    """`scan_interval: 0.001` would poll every millisecond: the options form's floor applies."""
    text = FILE.replace("scan_interval: 5.0", "scan_interval: 0.001")
    key, message = await refused(hass, text)
    assert key == "config_interval"
    assert message.startswith(f"Line {line_of(text, 'scan_interval: 0.001')}:")


async def test_size_refused_before_parsing(hass: HomeAssistant) -> None:
    """A 5 MB paste is refused at once (it held the event loop 24 s), never parsed."""
    text = FILE + "#" + "x" * (5 * 1024 * 1024) + "\n"
    key, message = await refused(hass, text)
    assert key == "config_too_large"
    assert f"{MAX_BYTES // 1024} KiB" in message


async def test_depth_refused_on_its_line(hass: HomeAssistant) -> None:
    """500 levels of nesting give an error on the field (they ended the flow uncaught)."""
    text = FILE + "spare: " + "[" * 500 + "]" * 500 + "\n"
    key, message = await refused(hass, text)
    assert key == "config_too_deep"
    assert message.startswith(f"Line {line_of(text, 'spare:')}:")


async def test_certificate_path_outside_the_config_folder(hass: HomeAssistant) -> None:
    """A certificate path in the file passes the connection form's configuration-folder check."""
    document = yaml.safe_load(dump_config(plc([], vendor="softplc", password="", port=8080)))
    document["connection"]["vendor_options"] = {"client_certificate": "/etc/ssl/private/plc.pem"}
    text = str(yaml.safe_dump(document, sort_keys=False))
    key, message = await refused(hass, text)
    assert key == "config_option"
    assert message.startswith(f"Line {line_of(text, 'client_certificate:')}: client_certificate")


@pytest.mark.parametrize("style", ["|", "|-"])
async def test_export_response_taken(hass: HomeAssistant, style: str) -> None:
    """The `export_config` action's response (the file under `yaml:`) is taken as the file.

    Folded (`>`), as the response view shows a file with long lines: test_export_menu.py.
    """
    body = "".join(f"  {line}\n" if line else "\n" for line in FILE.splitlines())
    result = await paste(hass, f"yaml: {style}\n{body}")
    assert (result["type"], result["step_id"]) == (FlowResultType.FORM, "connection_s7_smart")
    assert not result["errors"]
    broken = body.replace("scale: 0.1", "scale: tenth")
    key, message = await refused(hass, f"yaml: {style}\n{broken}")
    assert key == "config_bad_value"
    assert message.startswith(f"Line {line_of('yaml:\n' + broken, 'scale: tenth')}:")


def pasted_plc(sim: S7SmartSimulator, exposes: list[dict[str, Any]]) -> str:
    """Return the file of a PLC at the simulator, with a machine and the exposes."""
    level = point("level", "Level", "number", "VW100", "signed", min=0.0, max=30000.0)
    entry = MockConfigEntry(
        domain=DOMAIN,
        title="Boiler house",
        data=sim_data(sim),
        subentries_data=[device([*POINTS, level], title="Boiler")],
        version=2,
    )
    document = yaml.safe_load(dump_config(entry))
    for index, data in enumerate(exposes):
        document["subentries"].append(
            {"type": SUBENTRY_EXPOSE, "title": f"e{index}", "unique_id": None, "data": data}
        )
    return str(yaml.safe_dump(document, sort_keys=False))


async def test_host_and_certificate_before_any_secret(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """A pasted fingerprint is never trusted: the connection page (host, port) and the
    certificate page are shown before the password goes to the PLC."""
    result = await paste(hass, pasted_plc(s7_smart_ha_sim, []))
    assert result["step_id"] == "connection_s7_smart"
    assert suggested(result, "host") == s7_smart_ha_sim.host
    values = {str(m): suggested(result, str(m)) for m in result["data_schema"].schema}
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], values | {CONF_PASSWORD: SMART_PASSWORD}
    )
    assert result["step_id"] == "certificate"
    assert sum(s7_smart_ha_sim.calls.values()) == 0  # no login yet
    result = await confirm(hass, result, {})
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert s7_smart_ha_sim.calls["login"] >= 1


async def test_pasted_exposes_send_nothing(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, freezer: FrozenDateTimeFactory
) -> None:
    """Pasted exposes start with sending off; a page lists what each would write; nothing is
    written while the file is applied (send-on-start wrote M10.0 at setup before)."""
    hass.states.async_set("input_boolean.heat", "on")
    hass.states.async_set("sensor.outdoor", "5")
    heat = expose_data("input_boolean.heat", ("M10.0", "signed"), send_on_start=True)
    outdoor = expose_data("sensor.outdoor", ("VW200", "signed"), send_on_start=True, scale=3.0)
    result = await paste(hass, pasted_plc(s7_smart_ha_sim, [heat, outdoor]))
    result = await confirm(hass, result, {CONF_PASSWORD: SMART_PASSWORD})
    assert result["type"] is FlowResultType.CREATE_ENTRY
    await settle(hass, freezer, 5)
    entry = result["result"]
    assert s7_smart_ha_sim.calls["write"] == 0
    assert s7_smart_ha_sim.get("M10.0", "signed") == 0
    sent = [s for s in entry.subentries.values() if s.subentry_type == SUBENTRY_EXPOSE]
    assert [s.data[CONF_SEND] for s in sent] == [False, False]
    hass.states.async_set("sensor.outdoor", "6")
    await settle(hass, freezer, 5)
    assert s7_smart_ha_sim.calls["write"] == 0


async def test_exposes_listed_before_the_entry(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """The last page names each expose's entity, address and the value it would write now."""
    hass.states.async_set("sensor.outdoor", "5")
    outdoor = expose_data("sensor.outdoor", ("VW200", "signed"), scale=3.0)
    result = await paste(hass, pasted_plc(s7_smart_ha_sim, [outdoor]))
    values = {str(m): suggested(result, str(m)) for m in result["data_schema"].schema}
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], values | {CONF_PASSWORD: SMART_PASSWORD}
    )
    result = await hass.config_entries.flow.async_configure(result["flow_id"], {})
    assert result["step_id"] == "paste_exposes"
    assert result["description_placeholders"]["exposes"] == "- sensor.outdoor → VW200: 15"
    assert not hass.config_entries.async_entries(DOMAIN)


async def test_feedback_checked_when_sending_is_turned_on(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, freezer: FrozenDateTimeFactory
) -> None:
    """An expose feeding back on its own address (it ran VW100 from 5 to 24,575) is pasted off;
    turning it on runs the checks against the entities that now exist: refused."""
    s7_smart_ha_sim.set("VW100", 5, "signed")
    loop = expose_data("number.boiler_level", ("VW100", "signed"), scale=3.0)
    result = await paste(hass, pasted_plc(s7_smart_ha_sim, [loop]))
    result = await confirm(hass, result, {CONF_PASSWORD: SMART_PASSWORD})
    entry = result["result"]
    await settle(hass, freezer, 5)
    assert er.async_get(hass).async_get("number.boiler_level") is not None
    (sent,) = [s for s in entry.subentries.values() if s.subentry_type == SUBENTRY_EXPOSE]
    result = await hass.config_entries.subentries.async_init(
        (entry.entry_id, SUBENTRY_EXPOSE),
        context={"source": SOURCE_RECONFIGURE, "subentry_id": sent.subentry_id},
    )
    result = await hass.config_entries.subentries.async_configure(
        result["flow_id"], {"entity_id": suggested(result, "entity_id")}
    )
    values = {str(m): suggested(result, str(m)) for m in result["data_schema"].schema}
    values = {key: value for key, value in values.items() if value is not None}
    result = await hass.config_entries.subentries.async_configure(
        result["flow_id"], values | {CONF_SEND: True}
    )
    assert result["errors"] == {"address": "expose_feeds_back"}
    assert entry.subentries[sent.subentry_id].data[CONF_SEND] is False
    await settle(hass, freezer, 5)
    assert s7_smart_ha_sim.get("VW100", "signed") == 5
    assert s7_smart_ha_sim.calls["write"] == 0
