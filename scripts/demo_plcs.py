"""A new user's first steps with each simulator of the demo, through Home Assistant's APIs.

For every PLC family `scripts/develop` starts: add the PLC in the config flow (pinning its
certificate where it has one), add a device with points (picked from the PLC's variables
where it publishes them, else pasted as a table), wait until its entity shows the simulator's
value, write a new value through the entity's action and see it come back. Every simulator
holds the demo's machines (a boiler, a shutter, a pump; simulators/machines.py): import them
too, drive each entity through the action the frontend sends and read the address back from the
PLC (plc_bridge.read), and see the alarm word's Overheat sensor go on. Standard library only, as
scripts/demo_check.py that calls it.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
import time
from typing import Any

from hass_client import Hass, Socket

FLOW = "/api/config/config_entries/flow"
SUBENTRY_FLOW = "/api/config/config_entries/subentries/flow"


@dataclass(frozen=True, slots=True)
class Drive:
    """One action the frontend sends an entity, and the PLC value it must leave behind."""

    domain: str  # the entity's domain; the check takes the PLC's first entity of it
    service: str
    data: dict[str, Any]
    address: str  # read back from the PLC with plc_bridge.read
    data_type: str
    expected: Any
    reached: str = ""  # or this bit reads on: the end the command moves to (then it is released)


@dataclass(frozen=True, slots=True)
class Journey:
    """How a user adds one simulator's points, and the writable one that is checked."""

    table: str = ""  # pasted points (CSV with a header), when not picked
    pick: str = ""  # the browse filter whose first listed variable becomes the point
    machines: tuple[tuple[str, str | dict[str, Any]], ...] = ()
    """More devices: (name, a pasted table or an entity's page values, as the frontend posts)."""
    drives: tuple[Drive, ...] = ()  # the actions the check takes on those devices' entities


HEADER = "name,address,data_type,platform,min,max\n"
KINDS = "name,address,data_type,platform,unit,scale,min,max,step,read_only,role,value_map,bits\n"


def machines(
    word: str, bit: str, at: dict[str, str]
) -> tuple[tuple[str, str | dict[str, Any]], ...]:
    """Return the boiler and pump as tables and the shutter as its one page's values, at one
    simulator's addresses and types."""
    w, b = f"{word},", f"{bit},"
    return (
        (
            "Boiler",
            KINDS + f"Boiler,{at['water']},{w}climate,°C,0.1,,,,yes,current_temperature,,\n"
            f"Boiler,{at['target']},{w}climate,°C,0.1,5,30,0.5,no,target_temperature,,\n"
            f'Boiler,{at["hvac"]},{w}climate,,1,,,,no,hvac_mode,"0=off;1=heat",\n'
            f'Mode,{at["mode"]},{w}select,,1,,,,no,,"0=Off;1=Auto;2=Manual",\n'
            f'Alarms,{at["alarms"]},{w}event,,1,,,,yes,,,"0=Overheat;3=Low water"',
        ),
        (
            "Shutter",
            {
                "platform": "cover",
                "name": "Shutter",
                "device_class": "shutter",
                "commands": {
                    **{"open": at["open"], "open_data_type": bit},
                    **{"close": at["close"], "close_data_type": bit},
                },
                "limits": {
                    **{"open_limit": at["opened"], "open_limit_data_type": bit},
                    **{"closed_limit": at["closed"], "closed_limit_data_type": bit},
                },
            },
        ),
        (
            "Pump",
            KINDS + f"Pump,{at['running']},{b}switch,,1,,,,yes,state,,\n"
            f"Pump,{at['run']},{b}switch,,1,,,,no,command,,\n"
            f"Start,{at['start']},{b}button,,1,,,,no,,,",
        ),
    )


def drives(word: str, bit: str, at: dict[str, str]) -> tuple[Drive, ...]:
    """Return the frontend's actions on those machines and what each leaves in the PLC."""
    return (
        Drive("climate", "set_temperature", {"temperature": 22.5}, at["target"], word, 225),
        Drive("climate", "set_hvac_mode", {"hvac_mode": "heat"}, at["hvac"], word, 1),
        Drive("select", "select_option", {"option": "Manual"}, at["mode"], word, 2),
        # A level open is released once the open limit reads on (sooner than the check reads
        # the command where the simulator's program moves the shutter at once).
        Drive("cover", "open_cover", {}, at["open"], bit, True, reached=at["opened"]),
        Drive("switch", "turn_on", {}, at["run"], bit, True),
        Drive("button", "press", {}, at["start"], bit, True),
    )


# Read-only bits sit in other bytes (words) than written ones: a write that covers the byte
# of a read-only point is refused.
KIND_ADDRESSES = {
    "s7_smart": (
        "signed",
        "signed",
        "VW50 VW52 VW54 VW30 VW70 V60.0 V60.1 V62.0 V62.1 V63.0 V61.1 V61.2",
    ),
    "s7": (
        "INT",
        "BOOL",
        "DB1.DBW50 DB1.DBW52 DB1.DBW54 DB1.DBW30 DB1.DBW70 DB1.DBX60.0"
        " DB1.DBX60.1 DB1.DBX62.0 DB1.DBX62.1 DB1.DBX63.0 DB1.DBX61.1 DB1.DBX61.2",
    ),
    "softplc": (
        "INT",
        "BOOL",
        "N7:50 N7:52 N7:54 N7:30 N7:70 B3:4/0 B3:4/1 B3:6/0 B3:6/1 B3:7/0 B3:5/1 B3:5/2",
    ),
    "logo": (
        "INT",
        "BOOL",
        "VW50 VW52 VW54 VW30 VW70 V60.0 V60.1 V62.0 V62.1 V63.0 V61.1 V61.2",
    ),
    "tecomat": (
        "INT",
        "BOOL",
        "Boiler.water Boiler.target Boiler.hvac Boiler.mode Boiler.alarms Shutter.open"
        " Shutter.close Shutter.opened Shutter.closed Pump.running Pump.run Pump.start",
    ),
    "plcnext": (
        "INT",
        "BOOL",
        " ".join(
            f"HomeInstance.{name}"
            for name in (
                *("Boiler.Water", "Boiler.Target", "Boiler.Hvac", "Boiler.Mode", "Boiler.Alarms"),
                *("Shutter.Open", "Shutter.Close", "Shutter.Opened", "Shutter.Closed"),
                *("Pump.Running", "Pump.Run", "Pump.Start"),
            )
        ),
    ),
}
"""Where each simulator keeps the demo's machines (named, in ROLES' order): addresses, or the
public variables (TecoApi) and instance variables (PLCnext) of its demo program."""
ROLES = (
    *("water", "target", "hvac", "mode", "alarms"),
    *("open", "close", "opened", "closed", "running", "run", "start"),
)


def kinds(vendor: str) -> dict[str, Any]:
    """Return a simulator's machines and drives as Journey fields (none where it has none)."""
    if vendor not in KIND_ADDRESSES:
        return {}
    word, bit, addresses = KIND_ADDRESSES[vendor]
    at = dict(zip(ROLES, addresses.split(), strict=True))
    return {"machines": machines(word, bit, at), "drives": drives(word, bit, at)}


JOURNEYS = {
    "s7_smart": Journey(table=HEADER + "Setpoint,VD104,float,number,0,100", **kinds("s7_smart")),
    "tecomat": Journey(pick="Main.myObject3", **kinds("tecomat")),
    "plcnext": Journey(pick="MainInstance.Setpoint", **kinds("plcnext")),
    "softplc": Journey(table=HEADER + "Preset,T4:0.PRE,INT,number,0,30000", **kinds("softplc")),
    "s7": Journey(table=HEADER + "Setpoint,DB1.DBW6,INT,number,0,1000", **kinds("s7")),
    "logo": Journey(table=HEADER + "Setpoint,VW6,INT,number,0,1000", **kinds("logo")),
}
"""What each family's simulator offers a first user (see scripts/develop's hints)."""
WRITTEN = 21.0
"""The value every journey writes: inside each point's range."""


def add_plc(hass: Hass, sim: dict[str, Any]) -> str:
    """Add a simulator through the config flow as the dialog would; return the entry id."""
    flow = hass.call("POST", FLOW, {"handler": "plc_bridge"})
    step = f"{FLOW}/{flow['flow_id']}"
    if flow.get("type") == "menu":  # connect to a PLC, or paste a configuration
        flow = hass.call("POST", step, {"next_step_id": "vendor"})
    flow = hass.call("POST", step, {"vendor": sim["vendor"]})
    values: dict[str, Any] = {"host": sim["host"], "port": sim["port"]}
    names = {field["name"] for field in flow.get("data_schema", [])}
    if "tls" in names:
        values["tls"] = "pin" if sim["tls"] else "none"
    if sim["username"] is not None and "username" in names:
        values |= {"username": sim["username"], "password": sim["password"]}
    # The simulator names its fields as scripts/develop prints them ("Client certificate").
    options = {key.lower().replace(" ", "_"): value for key, value in sim["options"].items()}
    values |= {key: value for key, value in options.items() if key in names}
    flow = hass.call("POST", step, values)
    for _ in range(4):  # the pages that may follow: rack and slot, the certificate, the name
        if flow.get("type") != "form":
            break
        if flow.get("errors"):
            raise RuntimeError(f"{sim['vendor']}: {flow['step_id']} refused: {flow['errors']}")
        answer: dict[str, Any] = {}
        if flow["step_id"] == "s7_rack_slot":
            answer = sim.get("options", {})
        elif flow["step_id"] == "name":
            answer = {"name": f"Demo {sim['vendor']}"}
        flow = hass.call("POST", step, answer)
    if flow.get("type") != "create_entry":
        raise RuntimeError(f"{sim['vendor']}: the config flow ended with {flow}")
    return str(flow["result"]["entry_id"])


def add_device(hass: Hass, entry_id: str, journey: Journey, name: str = "Demo device") -> None:
    """Add a device with the journey's point, picked from the PLC's variables or pasted."""
    flow = hass.call("POST", SUBENTRY_FLOW, {"handler": [entry_id, "device"]})
    step = f"{SUBENTRY_FLOW}/{flow['flow_id']}"
    flow = hass.call("POST", step, {"name": name})
    if journey.pick:
        flow = hass.call("POST", step, {"next_step_id": "browse"})
        flow = hass.call("POST", step, {"filter": journey.pick})
        (field,) = flow["data_schema"]
        options = field["selector"]["select"]["options"]
        if flow.get("errors") and flow["errors"].get("base") != "browse_unlisted":
            raise RuntimeError(f"the pick list failed: {flow['errors']}")
        if not options:
            raise RuntimeError(f"no variable matches {journey.pick!r}")
        flow = hass.call("POST", step, {"variables": [options[0]["value"]]})
    else:
        flow = hass.call("POST", step, {"next_step_id": "import_points"})
        flow = hass.call("POST", step, {"table": journey.table})
    if flow.get("type") != "menu":
        raise RuntimeError(f"adding the point ended with {flow.get('errors') or flow}")
    flow = hass.call("POST", step, {"next_step_id": "save"})
    if flow.get("type") != "create_entry":
        raise RuntimeError(f"saving the device ended with {flow}")


def add_entity(hass: Hass, entry_id: str, name: str, page: dict[str, Any]) -> None:
    """Add a device with one entity of several addresses, built on its one page."""
    flow = hass.call("POST", SUBENTRY_FLOW, {"handler": [entry_id, "device"]})
    step = f"{SUBENTRY_FLOW}/{flow['flow_id']}"
    hass.call("POST", step, {"name": name})
    hass.call("POST", step, {"next_step_id": "composite"})
    flow = hass.call("POST", step, {"next_step_id": f"entity_{page['platform']}"})
    if flow.get("step_id") != "composite_entity":
        raise RuntimeError(f"the kinds' menu led to {flow}")
    shown = flow["data_schema"]
    sections = {field["name"]: {} for field in shown if field.get("type") == "expandable"}
    values = {key: value for key, value in page.items() if key != "platform"}
    flow = hass.call("POST", step, sections | values)  # a section's fields come nested
    if flow.get("type") != "menu":
        words = flow.get("description_placeholders")
        raise RuntimeError(f"the entity's page refused: {flow.get('errors')} {words}")
    flow = hass.call("POST", step, {"next_step_id": "save"})
    if flow.get("type") != "create_entry":
        raise RuntimeError(f"saving the device ended with {flow}")


def wait_for(ready: Callable[[], Any], timeout: float) -> Any:
    """Return the first true answer of `ready` within `timeout` seconds (else the last one)."""
    deadline = time.monotonic() + timeout
    while not (answer := ready()) and time.monotonic() < deadline:
        time.sleep(0.5)
    return answer


def number_of(ws: Socket, entry_id: str, domain: str = "number") -> str | None:
    """Return the entity id of the entry's first entity of a domain (the journey's point)."""
    entities = ws.call("config/entity_registry/list")
    found = [
        entity["entity_id"]
        for entity in entities
        if entity["config_entry_id"] == entry_id
        and entity["entity_id"].startswith(f"{domain}.")
        and entity.get("entity_category") is None
    ]
    return found[0] if found else None


def plc_value(hass: Hass, entry_id: str, drive: Drive) -> Any:
    """Return what the PLC holds at the drive's address, read through plc_bridge.read.

    The answer names the address as the PLC family spells it (a PLCnext path with its
    component, `Arp.Plc.Eclr/...`): the one value asked for is taken whatever its name.
    """
    point = {"address": drive.address, "data_type": drive.data_type}
    body = {"config_entry_id": entry_id, "points": [point]}
    answer = hass.call("POST", "/api/services/plc_bridge/read?return_response", body)
    return next(iter(answer["service_response"]["values"].values()), None)


def drive_kinds(hass: Hass, ws: Socket, entry_id: str, vendor: str) -> list[str]:
    """Add the journey's machines, take each action as the frontend does, see the PLC change."""
    plan = JOURNEYS[vendor]
    for name, made in plan.machines:
        if isinstance(made, dict):
            add_entity(hass, entry_id, name, made)
            print(f"demo: {vendor}: {name} added on its entity's page", flush=True)
        else:
            add_device(hass, entry_id, Journey(table=made), name)
    alarm = wait_for(lambda: overheat(ws, entry_id), 30) if plan.machines else None
    before = _state(hass, alarm) if alarm else None
    problems = []
    for drive in plan.drives:
        try:
            problem = take(hass, ws, entry_id, drive, vendor)
        except RuntimeError as err:  # a refused action fails its drive, not the others
            problem = str(err)
        if problem:
            problems.append(f"{drive.domain}.{drive.service}: {problem}")
    if plan.machines and alarm is None:
        problems.append("alarm word: no Overheat binary sensor")
    elif alarm is not None:
        # The simulator raises Overheat while the water is above the set point just written.
        if wait_for(lambda: _state(hass, alarm) == "on", 30):
            print(f"demo: {vendor}: alarm word: {alarm} {before} -> on", flush=True)
        else:
            problems.append(f"alarm word: {alarm} is {_state(hass, alarm)}, not on")
    return problems


def overheat(ws: Socket, entry_id: str) -> str | None:
    """Return the entity id of the entry's Overheat binary sensor (of the alarm word)."""
    names = {s["entity_id"]: s["attributes"].get("friendly_name") for s in ws.call("get_states")}
    for entity in ws.call("config/entity_registry/list"):
        name = str(names.get(entity["entity_id"]))
        if entity["config_entry_id"] == entry_id and name.endswith("Overheat"):
            return str(entity["entity_id"])
    return None


def take(hass: Hass, ws: Socket, entry_id: str, drive: Drive, vendor: str) -> str:
    """Take one drive; print what the PLC held before and after, or return what went wrong."""
    entity = wait_for(lambda: number_of(ws, entry_id, drive.domain), 30)
    if entity is None or not wait_for(
        lambda: _state(hass, entity) not in (None, "unavailable"), 30
    ):
        return f"no available {drive.domain} entity ({entity})"
    before = plc_value(hass, entry_id, drive)
    service = f"/api/services/{drive.domain}/{drive.service}"
    hass.call("POST", service, {"entity_id": entity, **drive.data})
    end = Drive(drive.domain, drive.service, {}, drive.reached, drive.data_type, True)

    def done() -> str:
        """What shows the action done: its value written, or the end its command moves to."""
        if plc_value(hass, entry_id, drive) == drive.expected:
            return f"{drive.address} {before!r} -> {drive.expected!r}"
        if drive.reached and plc_value(hass, entry_id, end) is True:
            return f"{drive.reached} (the end it moves to) -> True, the command released"
        return ""

    if not (shown := wait_for(done, 15)):
        now = plc_value(hass, entry_id, drive)
        return f"{entity}: {drive.address} is {now!r}, not {drive.expected!r}"
    print(f"demo: {vendor}: {drive.domain}.{drive.service} on {entity}: {shown}", flush=True)
    return ""


def journey(hass: Hass, ws: Socket, sim: dict[str, Any]) -> list[str]:
    """Run one family's journey; return what went wrong (nothing when all is well)."""
    vendor = sim["vendor"]
    plan = JOURNEYS.get(vendor)
    if plan is None:
        return [f"{vendor}: the demo check has no journey for this simulator"]
    try:
        entry_id = add_plc(hass, sim)
        loaded = wait_for(
            lambda: (
                {e["entry_id"]: e for e in ws.call("config_entries/get")}[entry_id]["state"]
                == "loaded"
            ),
            30,
        )
        if not loaded:
            return [f"{vendor}: the PLC did not load"]
        add_device(hass, entry_id, plan)
        entity = wait_for(lambda: number_of(ws, entry_id), 30)
        if entity is None:
            return [f"{vendor}: the point's number entity did not appear"]
        state = wait_for(lambda: _state(hass, entity) not in (None, "unavailable", "unknown"), 30)
        if not state:
            return [f"{vendor}: {entity} shows no value: {_state(hass, entity)}"]
        hass.call("POST", "/api/services/number/set_value", {"entity_id": entity, "value": WRITTEN})
        if not wait_for(lambda: _number(_state(hass, entity)) == WRITTEN, 30):
            return [f"{vendor}: {entity} shows {_state(hass, entity)} after writing {WRITTEN}"]
        return [f"{vendor}: {problem}" for problem in drive_kinds(hass, ws, entry_id, vendor)]
    except Exception as err:  # any step of a journey that fails is one problem of its family
        return [f"{vendor}: {type(err).__name__}: {err}"]
    return []


def _state(hass: Hass, entity: str) -> str | None:
    """Return an entity's state, None while it has none."""
    answer = hass.call("GET", f"/api/states/{entity}")
    return answer.get("state") if isinstance(answer, dict) else None


def _number(state: str | None) -> float | None:
    """Return a state as a number, None when it is none."""
    try:
        return float(state) if state is not None else None
    except ValueError:
        return None
