"""Export where the user is: the PLC's options show its file; the paste takes it in every form.

The Export page of the options menu shows the file in a Markdown code block; pasted into Add
integration (as copied from the block, or as the `export_config` action's response view shows
it: the file under `yaml:`, literal or folded with its long lines wrapped, with or without
that `yaml:` line), it gives the same PLC: entities, unique ids, states and writes.
"""

from __future__ import annotations

from pathlib import Path
import re
from typing import Any

from homeassistant.components.switch import DOMAIN as SWITCH_DOMAIN
from homeassistant.config_entries import ConfigEntry
from homeassistant.const import ATTR_ENTITY_ID, SERVICE_TURN_ON
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
import pytest
import yaml

from custom_components.plc_bridge.flows.options_flow import code_block
from custom_components.plc_bridge.model.config_file import dump_config
from custom_components.plc_bridge.model.yaml_text import YamlTextError, read_yaml
from simulators.s7_smart import S7SmartSimulator
from tests.flows.forms import strings_at, translated
from tests.test_config_file import VENDORS, confirm, contents, entities, original, paste, states

pytestmark = pytest.mark.no_pacing

OPTIONS = ("options",)
JS_YAML_RESPONSE = Path(__file__).with_name("export_response_js_yaml.txt")
"""The response view's text of an exported file, as the frontend's YAML dumper (js-yaml 4,
`dump(response)`, 80 columns) wrote it: the file folded (`>`), its long lines wrapped."""


LONG_TITLE = "Boiler house of the north wing, second floor, beside the heat exchangers and pumps"


class _Block(str):
    """A text the dumper writes as a block scalar of the style asked."""

    style = "|"


class _Folded(_Block):
    """A text the dumper writes folded, its long lines wrapped at 80 columns."""

    style = ">"


class _Dumper(yaml.SafeDumper):
    """A YAML dumper writing _Block texts in their block style."""


_Dumper.add_multi_representer(
    _Block,
    lambda dumper, text: dumper.represent_scalar("tag:yaml.org,2002:str", text, style=text.style),
)


def response_view(text: str, style: str) -> str:
    """Return the file as an action's response view shows it: under `yaml:`, in a block style."""
    block = _Folded(text) if style == ">" else _Block(text)
    view = yaml.dump({"yaml": block}, Dumper=_Dumper, width=80, allow_unicode=True)
    assert view.startswith(f"yaml: {style}")
    assert yaml.safe_load(view)["yaml"] == text  # a faithful dump, whatever its folding
    return str(view)


def code_of(description: str) -> str:
    """Return what a Markdown code block's copy button copies: the text between its fences."""
    match = re.search(r"^(`{3,})yaml\n(.*)\n\1$", description, re.S | re.M)
    assert match is not None, description
    return match.group(2) + "\n"


def by_unique_id(hass: HomeAssistant, entity_ids: dict[str, str]) -> dict[str, Any]:
    """Return each entity's state and attributes by its unique id (ids follow the title)."""
    shown = states(hass, list(entity_ids.values()))
    return {uid: shown[eid] for uid, eid in entity_ids.items()}


async def export_page(hass: HomeAssistant, entry: ConfigEntry) -> dict[str, Any]:
    """Open the PLC's options and choose Export; return the page."""
    result = await hass.config_entries.options.async_init(entry.entry_id)
    assert result["type"] is FlowResultType.MENU
    assert result["menu_options"] == ["polling", "export"]
    assert set(result["menu_options"]) == set(strings_at("options", "step", "init", "menu_options"))
    result = await hass.config_entries.options.async_configure(
        result["flow_id"], {"next_step_id": "export"}
    )
    return translated(result, *OPTIONS)


async def test_export_page_shows_the_file(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator
) -> None:
    """The page shows the file in a code block, as the action returns it; submitting it
    changes nothing."""
    entry = await original(hass, VENDORS["s7_smart"], s7_smart_ha_sim, {})
    options = dict(entry.options)
    result = await export_page(hass, entry)
    assert (result["type"], result["step_id"]) == (FlowResultType.FORM, "export")
    description = strings_at("options", "step", "export", "description")
    assert "{configuration}" in description
    shown = description.format(**result["description_placeholders"])
    assert code_of(shown) == dump_config(entry)
    assert result["description_placeholders"]["title"] == entry.title
    result = await hass.config_entries.options.async_configure(result["flow_id"], {})
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert dict(entry.options) == options


def test_code_block_fence_outlasts_backticks() -> None:
    """A text holding backticks (a name, say) keeps its code block whole."""
    assert code_block("a: 1\n") == "```yaml\na: 1\n```"
    assert code_block("name: a ```` b\n") == "`````yaml\nname: a ```` b\n`````"


@pytest.mark.parametrize("form", ["code block", "|", ">", "> without its yaml line"])
async def test_exported_in_the_menu_pasted_again(
    hass: HomeAssistant, s7_smart_ha_sim: S7SmartSimulator, form: str
) -> None:
    """Export in the options, remove the PLC, paste: the same entities, unique ids, states; a
    switch of the new entry writes the PLC as the old one did."""
    vendor = VENDORS["s7_smart"]
    entry = await original(hass, vendor, s7_smart_ha_sim, {})
    hass.config_entries.async_update_entry(entry, title=LONG_TITLE)  # a line to wrap
    await hass.async_block_till_done()
    before = entities(hass, entry)
    shown = by_unique_id(hass, before)
    kept = contents(entry)
    page = await export_page(hass, entry)
    text = code_of(page["description_placeholders"]["configuration"])
    await hass.config_entries.options.async_configure(page["flow_id"], {})
    if form in ("|", ">"):
        text = response_view(text, form)
    elif form.startswith(">"):
        text = response_view(text, ">").split("\n", 1)[1]
    assert await hass.config_entries.async_remove(entry.entry_id)
    await hass.async_block_till_done()
    result = await confirm(hass, await paste(hass, text), vendor.secrets(s7_smart_ha_sim))
    assert result["type"] is FlowResultType.CREATE_ENTRY
    await hass.async_block_till_done()
    new = result["result"]
    assert contents(new) == kept
    assert new.unique_id == entry.unique_id
    # Neither a serial nor a MAC: the entities are keyed by the entry id, which is new.
    after = {
        uid.replace(new.entry_id, entry.entry_id): eid for uid, eid in entities(hass, new).items()
    }
    assert set(after) == set(before)
    assert by_unique_id(hass, after) == shown
    (pump,) = [eid for uid, eid in entities(hass, new).items() if uid.endswith("_pump")]
    await hass.services.async_call(
        SWITCH_DOMAIN, SERVICE_TURN_ON, {ATTR_ENTITY_ID: pump}, blocking=True
    )
    assert s7_smart_ha_sim.get("Q0.0") == 1


def test_frontend_response_view_read() -> None:
    """The frontend's own folded dump of a file reads as the file, with or without `yaml:`;
    an error names the line of the pasted text."""
    view = JS_YAML_RESPONSE.read_text(encoding="utf-8")
    file = yaml.safe_load(view)["yaml"]
    assert read_yaml(view).data == yaml.safe_load(file)
    body = view.split("\n", 1)[1]
    assert read_yaml(body).data == yaml.safe_load(file)
    assert read_yaml(view).line(("title",)) == next(
        n for n, line in enumerate(view.splitlines(), 1) if "title: Boiler house" in line
    )
    for text in (view, body):
        broken = text.replace("    host: 192.0.2.10\n", "    host: [192.0.2.10\n")
        with pytest.raises(YamlTextError) as err:
            read_yaml(broken)
        host = next(n for n, line in enumerate(broken.splitlines(), 1) if "host: [" in line)
        assert int(err.value.placeholders["line"]) in (host, host + 1)  # where YAML sees it


@pytest.mark.parametrize(
    ("text", "key"),
    [
        ("yaml: 42\n", "config_not_ours"),
        ("points: []\ndevices: {}\n", "config_not_ours"),
        ("yaml: >\n  plc_bridge: [1\n", "config_malformed"),
    ],
)
async def test_other_text_refused_clearly(hass: HomeAssistant, text: str, key: str) -> None:
    """What is no exported file, as a file or a response, gets a clear error on the field."""
    result = await paste(hass, text)
    assert (result["type"], result["step_id"]) == (FlowResultType.FORM, "paste_configuration")
    assert result["errors"] == {"configuration": key}
