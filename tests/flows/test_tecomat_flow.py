"""Config and point flows of a Tecomat PLC against its simulator: Digest/Basic, browsing."""

from __future__ import annotations

from collections.abc import AsyncGenerator
from typing import Any
from unittest.mock import AsyncMock

from freezegun.api import FrozenDateTimeFactory
from homeassistant.config_entries import SOURCE_USER, ConfigEntryState
from homeassistant.const import CONF_HOST, CONF_PASSWORD, CONF_PORT, CONF_USERNAME
from homeassistant.core import HomeAssistant
from homeassistant.data_entry_flow import FlowResultType
import pytest

from custom_components.plc_bridge.const import CONF_TLS, CONF_VENDOR, DOMAIN, SUBENTRY_DEVICE
from simulators.tecomat import DEFAULT_PASSWORD, DEFAULT_USER, TecomatSimulator
from tests.entries import point, read_edits
from tests.flows.forms import error_message, translated
from tests.harness import TECOMAT_SERIAL, make_tecomat_entry
from tests.loopback import running

CONFIG = ("config",)
DEVICES = ("config_subentries", SUBENTRY_DEVICE)


@pytest.fixture(params=["digest", "basic"])
async def auth_sim(request: pytest.FixtureRequest) -> AsyncGenerator[TecomatSimulator]:
    """A Tecomat simulator asking for Digest or for Basic authentication."""
    async with running(TecomatSimulator(auth=request.param, bench=0)) as sim:
        yield sim


async def connection_form(hass: HomeAssistant) -> dict[str, Any]:
    """Start a user flow and pick the Tecomat vendor; return the connection form."""
    result = await hass.config_entries.flow.async_init(DOMAIN, context={"source": SOURCE_USER})
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {"next_step_id": "vendor"}
    )
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], {CONF_VENDOR: "tecomat"}
    )
    assert result["step_id"] == "connection_tecomat"
    return translated(result, *CONFIG)


def connection(sim: TecomatSimulator, auth: str, **changes: Any) -> dict[str, Any]:
    """Return the connection form input for the simulator."""
    values = {
        CONF_HOST: sim.host,
        CONF_PORT: sim.port,
        CONF_TLS: "none",
        CONF_USERNAME: DEFAULT_USER,
        CONF_PASSWORD: DEFAULT_PASSWORD,
        "auth": auth,
        "clock_variable": "setTime",
    }
    return values | changes


async def test_connection_form_fields(hass: HomeAssistant) -> None:
    """The form offers the TecoApi fields: port 80, no TLS, Digest by default."""
    result = await connection_form(hass)
    schema = {str(marker): marker for marker in result["data_schema"].schema}
    assert list(schema) == [
        CONF_HOST,
        CONF_PORT,
        CONF_TLS,
        CONF_USERNAME,
        CONF_PASSWORD,
        "auth",
        "clock_variable",
    ]
    assert schema[CONF_PORT].default() == 80
    assert schema[CONF_TLS].default() == "none"
    assert schema["auth"].default() == "digest"


async def test_creates_entry(
    hass: HomeAssistant, auth_sim: TecomatSimulator, mock_setup_entry: AsyncMock
) -> None:
    """Digest or Basic: the entry is keyed by GetInfo's serial number."""
    method = auth_sim.auth.method
    result = await connection_form(hass)
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], connection(auth_sim, method)
    )
    assert result["type"] is FlowResultType.CREATE_ENTRY
    assert result["title"] == "Fx2 CP2080 127.0.0.1"
    assert result["result"].unique_id == TECOMAT_SERIAL
    assert result["data"] == {
        CONF_VENDOR: "tecomat",
        CONF_HOST: auth_sim.host,
        CONF_PORT: auth_sim.port,
        CONF_TLS: "none",
        CONF_USERNAME: DEFAULT_USER,
        CONF_PASSWORD: DEFAULT_PASSWORD,
        "fingerprint": "",
        "vendor_options": {"auth": method, "clock_variable": "setTime"},
    }
    assert auth_sim.calls["GetInfo"] == 1
    assert sum(auth_sim.auth.accepted.values()) >= 1


@pytest.mark.parametrize(
    ("changes", "field"),
    [
        ({CONF_PASSWORD: "wrong"}, CONF_PASSWORD),
        ({CONF_USERNAME: "nobody"}, CONF_PASSWORD),
    ],
)
async def test_wrong_credentials(
    hass: HomeAssistant,
    auth_sim: TecomatSimulator,
    mock_setup_entry: AsyncMock,
    changes: dict[str, str],
    field: str,
) -> None:
    """Credentials the PLC refuses show invalid_auth on the password; fixing them creates."""
    method = auth_sim.auth.method
    result = await connection_form(hass)
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], connection(auth_sim, method, **changes)
    )
    assert result["type"] is FlowResultType.FORM
    assert translated(result, *CONFIG)["errors"] == {field: "invalid_auth"}
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], connection(auth_sim, method)
    )
    assert result["type"] is FlowResultType.CREATE_ENTRY


async def test_wrong_method(
    hass: HomeAssistant, auth_sim: TecomatSimulator, mock_setup_entry: AsyncMock
) -> None:
    """Choosing the method the PLC does not use is an authentication error too."""
    other = "basic" if auth_sim.auth.method == "digest" else "digest"
    result = await connection_form(hass)
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], connection(auth_sim, other)
    )
    assert result["errors"] == {CONF_PASSWORD: "invalid_auth"}


async def test_clock_variable_checked(
    hass: HomeAssistant, tecomat_ha_sim: TecomatSimulator
) -> None:
    """A clock variable that is no variable path is refused with the client's words."""
    result = await connection_form(hass)
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], connection(tecomat_ha_sim, "digest", clock_variable="set time")
    )
    assert result["errors"] == {"base": "invalid_options"}
    problem = "clock variable: 'set time' is not a TecoApi variable path; write it like"
    assert error_message(result, "base", *CONFIG).startswith(
        f"The connection settings are not valid: {problem}"
    )
    assert tecomat_ha_sim.requests == 0


async def open_pick(hass: HomeAssistant, entry: Any, text: str = "") -> Any:
    """Start a device, browse the PLC with a filter; return the pick form."""
    result = await hass.config_entries.subentries.async_init(
        (entry.entry_id, SUBENTRY_DEVICE), context={"source": SOURCE_USER}
    )
    result = await hass.config_entries.subentries.async_configure(
        result["flow_id"], {"name": "Heating"}
    )
    result = await hass.config_entries.subentries.async_configure(
        result["flow_id"], {"next_step_id": "browse"}
    )
    result = await hass.config_entries.subentries.async_configure(
        result["flow_id"], {"filter": text}
    )
    assert translated(result, *DEVICES)["step_id"] == "pick"
    return result


def labels_of(result: Any) -> dict[str, str]:
    """Return the pick list's labels and values."""
    options = result["data_schema"].schema["variables"].config["options"]
    return {option["label"]: option["value"] for option in options}


async def test_browse_lists_leaves_and_picks(
    hass: HomeAssistant, tecomat_ha_sim: TecomatSimulator, freezer: FrozenDateTimeFactory
) -> None:
    """Browsing the real simulator: leaves of structs, arrays and Main; a 5.3 object fills in."""
    entry = make_tecomat_entry(
        hass, tecomat_ha_sim, [point("dint", "Dint", "sensor", "plcData.varDint", "DINT")]
    )
    assert await hass.config_entries.async_setup(entry.entry_id)
    await hass.async_block_till_done()
    labels: dict[str, str] = {}
    for text in ("myObject.", "arr", "plcData.", "Main.", "setTime"):  # 50 listed at most
        labels |= labels_of(await open_pick(hass, entry, text))
    for label in (
        "myObject.favorites.color (STRING?)",
        "myObject.interests[2] (STRING?)",
        "arr2[2][3] (REAL?)",
        "arr3[1][2][3] (DINT?)",  # TecoApi sends no types: JSON integers are guessed DINT
        "myObject.married (BOOL?)",
        "plcData.varStringArray[5] (STRING?)",
        "plcData.varDT (DT?)",
        "requested temperature – Main.myObject3.value (REAL?)",
        "circulation pump – Main.pump.value (BOOL?)",
    ):
        assert label in labels, label
    assert "plcData.varDint (DINT?)" not in labels  # configured already
    assert "setTime (DT?)" in labels

    result = await open_pick(hass, entry, "main.myobject")
    labels = labels_of(result)
    assert all("Main.myObject" in label for label in labels)
    result = await hass.config_entries.subentries.async_configure(
        result["flow_id"],
        {
            "variables": [
                labels["requested temperature – Main.myObject3.value (REAL?)"],
                labels["outside temperature – Main.myObject1.value (REAL?)"],
            ]
        },
    )
    result = await hass.config_entries.subentries.async_configure(
        result["flow_id"], {"next_step_id": "save"}
    )
    assert result["type"] is FlowResultType.CREATE_ENTRY
    await hass.async_block_till_done()
    (heating,) = [s for s in entry.subentries.values() if s.title == "Heating"]
    points = {data["address"]: data for data in heating.data["points"].values()}
    assert points["Main.myObject3.value"] == {
        "name": "requested temperature",
        "platform": "number",
        "address": "Main.myObject3.value",
        "data_type": "REAL",
        "unit_of_measurement": "°C",
        "min": 10.0,
        "max": 30.0,
        "scale": 1.0,
        "offset": 0.0,
        "read_only": False,
    }
    # A read-only 5.3 object becomes a sensor without a range (min = max = 0 means none).
    outside = points["Main.myObject1.value"]
    assert (outside["platform"], outside["read_only"]) == ("sensor", True)
    assert "min" not in outside
    await read_edits(hass, freezer)
    assert hass.states.get("number.heating_requested_temperature").state == "23.0"
    assert entry.state is ConfigEntryState.LOADED


async def test_same_plc_aborts(hass: HomeAssistant, tecomat_ha_sim: TecomatSimulator) -> None:
    """A second flow for the same PLC aborts: the serial number is configured already."""
    make_tecomat_entry(hass, tecomat_ha_sim, [])
    result = await connection_form(hass)
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"], connection(tecomat_ha_sim, "digest")
    )
    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "already_configured"


async def test_reconfigure(
    hass: HomeAssistant, tecomat_ha_sim: TecomatSimulator, mock_setup_entry: AsyncMock
) -> None:
    """Reconfigure shows the TecoApi page without credentials, filled in; the same PLC is kept."""
    entry = make_tecomat_entry(hass, tecomat_ha_sim)
    result = translated(await entry.start_reconfigure_flow(hass), *CONFIG)
    assert result["step_id"] == "reconfigure_tecomat"
    fields = [str(marker) for marker in result["data_schema"].schema]
    assert fields == [CONF_HOST, CONF_PORT, CONF_TLS, "auth", "clock_variable"]
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"],
        {CONF_HOST: tecomat_ha_sim.host, CONF_PORT: tecomat_ha_sim.port, CONF_TLS: "none"}
        | {"auth": tecomat_ha_sim.auth.method, "clock_variable": "set time"},
    )
    assert translated(result, *CONFIG)["errors"] == {"base": "invalid_options"}
    assert result["step_id"] == "reconfigure_tecomat"
    assert tecomat_ha_sim.requests == 0
    result = await hass.config_entries.flow.async_configure(
        result["flow_id"],
        {CONF_HOST: tecomat_ha_sim.host, CONF_PORT: tecomat_ha_sim.port, CONF_TLS: "none"}
        | {"auth": tecomat_ha_sim.auth.method, "clock_variable": "setTime"},
    )
    assert result["type"] is FlowResultType.ABORT
    assert result["reason"] == "reconfigure_successful"
    assert entry.data[CONF_USERNAME] == DEFAULT_USER  # the credentials stay as they were
    assert entry.data["vendor_options"]["clock_variable"] == "setTime"
