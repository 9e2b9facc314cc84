"""The typed model of a stored PLC: read from an entry or a file alike, written back unchanged,
and one validation whose problems name the stored value they concern."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from homeassistant.config_entries import ConfigSubentryData
from homeassistant.const import CONF_HOST, CONF_PASSWORD, CONF_PORT
import pytest
from pytest_homeassistant_custom_component.common import MockConfigEntry

from custom_components.plc_bridge.const import (
    CONF_MAC,
    CONF_OPTIONS,
    CONF_TLS,
    CONF_VENDOR,
    DOMAIN,
    SUBENTRY_EXPOSE,
)
from custom_components.plc_bridge.model.config_file import dump_config, load_config
from custom_components.plc_bridge.model.plc_config import (
    Connection,
    PlcConfig,
    PollOptions,
    file_problems,
    host_valid,
)
from custom_components.plc_bridge.plc.vendors import client_class
from tests.entries import POINTS, device, legacy_point, point
from tests.model.test_config_file_text import DATA

SMART = client_class("s7_smart")
EXPOSE = ConfigSubentryData(
    data={
        "entity_id": "sensor.outside",
        "address": "VW300",
        "data_type": "signed",
        "scale": 10.0,
        "offset": 0.0,
        "cooldown": 1.0,
        "resend": 0.0,
        "send_on_start": False,
    },
    subentry_type=SUBENTRY_EXPOSE,
    title="sensor.outside → VW300",
    unique_id=None,
)
COVER = [
    point("open", "Shutter", "cover", "Q0.1", "signed", role="open", travel_time=20.0),
    point("close", "Shutter", "cover", "Q0.2", "signed", role="close", travel_time=20.0),
]


def entry(
    subentries: list[Any] | None = None, options: dict[str, Any] | None = None, **data: Any
) -> MockConfigEntry:
    """Return a PLC's entry (not added): machines, a composite, an expose, a version 1 point."""
    return MockConfigEntry(
        domain=DOMAIN,
        title="Boiler house",
        data=DATA | data,
        options={"scan_interval": 5} if options is None else options,
        subentries_data=subentries
        if subentries is not None
        else [device(POINTS), device(COVER, "shutters", "Shutters"), EXPOSE],
        version=2,
        minor_version=2,
    )


@pytest.mark.parametrize(
    "stored",
    [
        entry(),
        entry(options={}, mac="00:1b:1b:00:00:01", tls="none"),
        entry([legacy_point(POINTS[0])], options={"scan_interval": 5.0, "slow_interval": 60}),
    ],
    ids=["machines", "bare", "version 1"],
)
def test_written_back_unchanged(stored: MockConfigEntry) -> None:
    """What the model reads from an entry it writes back exactly: keys, values and types."""
    data, options, subentries = PlcConfig.from_entry(stored).storage()
    assert (data, options) == (dict(stored.data), dict(stored.options))
    assert [type(value) for value in options.values()] == [
        type(value) for value in stored.options.values()
    ]
    assert subentries == [
        ConfigSubentryData(
            data=dict(sub.data),
            subentry_type=sub.subentry_type,
            title=sub.title,
            unique_id=sub.unique_id,
        )
        for sub in stored.subentries.values()
    ]


def test_file_and_entry_read_alike() -> None:
    """The entry and the file exported from it give the same points, options and problems."""
    stored = entry()
    from_entry = PlcConfig.from_entry(stored)
    from_file = load_config(dump_config(stored), version=2).plc()
    assert from_file.options == from_entry.options
    assert from_file.connection == Connection.from_data(
        {key: value for key, value in DATA.items() if key != CONF_PASSWORD}
    )
    assert {key: c.stored() for key, c in from_file.point_configs().items()} == {
        key: c.stored() for key, c in from_entry.point_configs().items()
    }
    assert from_entry.problems(SMART) == from_file.problems(SMART) == []


def test_connection_refused_on_its_value() -> None:
    """A blank host, a port out of range and an unknown TLS mode: each on its own path."""
    problems = PlcConfig.from_entry(entry(host=" ", port=70000, tls="maybe")).problems(SMART)
    assert [(p.path, p.key, p.field) for p in problems] == [
        (("connection", CONF_HOST), "config_bad_value", CONF_HOST),
        (("connection", CONF_PORT), "config_bad_value", CONF_PORT),
        (("connection", CONF_TLS), "config_bad_value", CONF_TLS),
    ]


@pytest.mark.parametrize(
    "host",
    [
        "192.0.2.10",
        "plc",
        "plc-1.boiler.local",
        "plc.local.",
        "fe80::1",
        "fe80::1%eth0",
        "kotelna_2",
    ],
)
def test_hosts_taken(host: str) -> None:
    """A host name (any script, underscores) or an IPv4 or IPv6 address alone is taken."""
    assert host_valid(host)


@pytest.mark.parametrize(
    "host",
    [
        "",
        " plc",
        "https://plc",
        "plc/Web_api",
        "plc:443",
        "[fe80::1]",
        "admin@plc",
        "plc .local",
        "plc..local",
        "-plc",
        "p" * 64,
    ],
)
def test_hosts_refused(host: str) -> None:
    """A scheme, a path, a port, a user, blanks or empty labels: not a host alone."""
    assert not host_valid(host)
    (problem,) = Connection.from_data(DATA | {CONF_HOST: host}).problems()
    assert (problem.path, problem.key) == (("connection", CONF_HOST), "config_bad_value")
    assert (problem.field, problem.field_key) == (CONF_HOST, "invalid_host")


def test_tls_of_the_vendor() -> None:
    """A TLS mode the vendor does not offer is refused; one left out (older entries) is not."""
    s7 = {**DATA, CONF_VENDOR: "s7", CONF_PORT: 102}
    (problem,) = Connection.from_data(s7).problems()
    assert (problem.path, problem.field_key) == (("connection", CONF_TLS), "invalid_tls")
    assert problem.placeholders["kind"] == "none"
    assert (
        list(Connection.from_data({k: v for k, v in s7.items() if k != CONF_TLS}).problems()) == []
    )


def test_vendor_options_checked_by_the_client() -> None:
    """A vendor option its client refuses: on its own field and value, else on the form."""
    tsap = {"connection": "tsap", "remote_tsap": "zz"}
    s7 = {**DATA, CONF_VENDOR: "s7", CONF_PORT: 102, CONF_TLS: "none", CONF_OPTIONS: tsap}
    (problem,) = Connection.from_data(s7).problems()
    assert problem.path == ("connection", CONF_OPTIONS, "remote_tsap")
    assert (problem.key, problem.field, problem.field_key) == (
        "config_connection_option",
        "remote_tsap",
        "invalid_options",
    )
    clock = {**DATA, CONF_VENDOR: "tecomat", CONF_TLS: "none"}
    (problem,) = Connection.from_data(clock | {CONF_OPTIONS: {"clock_variable": "a b"}}).problems()
    assert (problem.path, problem.field) == (("connection", CONF_OPTIONS), "")
    assert problem.placeholders["problem"].startswith("clock variable: 'a b'")


def test_certificate_files_inside_the_config_folder(tmp_path: Path) -> None:
    """A certificate path outside the configuration folder is refused on its option."""
    outside = {"client_certificate": "/etc/ssl/private/plc.pem"}
    resolved, (problem,) = file_problems("softplc", str(tmp_path), outside, {})
    assert resolved == {}
    assert problem.path == ("connection", CONF_OPTIONS, "client_certificate")
    assert (problem.key, problem.field_key) == ("config_option", "pem_outside_config")
    assert file_problems("s7_smart", str(tmp_path), outside, {}) == ({}, [])


def test_point_problems_name_their_value() -> None:
    """An address the parser refuses, and a point a form refuses: the path of the value."""
    bad = entry([device([point("t", "T", "sensor", "VX1", "float")], "boiler")])
    (problem,) = PlcConfig.from_entry(bad).problems(SMART)
    assert problem.path == ("subentries", "boiler", "data", "points", "t", "address")
    assert (problem.key, problem.field_key) == ("config_bad_address", "invalid_address")
    zero = entry([device([point("t", "T", "sensor", "VD1", "float", scale=0.0)], "boiler")])
    (problem,) = PlcConfig.from_entry(zero).problems(SMART)
    assert problem.path == ("subentries", "boiler", "data", "points", "t", "scale")
    assert (problem.key, problem.field_key) == ("config_point", "scale_zero")


def test_intervals_checked_as_the_options_form_checks() -> None:
    """Below the vendor's pace, or out of order: the options form's error on its field."""
    fast = PlcConfig.from_entry(entry(options={"scan_interval": 0.2}))
    problem = fast.interval_problems(SMART)[0]
    assert (problem.path, problem.field, problem.field_key) == (
        ("options", "scan_interval"),
        "scan_interval",
        "scan_interval_too_short",
    )
    plc = PlcConfig.from_entry(entry())
    assert plc.interval_problems(SMART) == []
    given = {"scan_interval": 5.0, "slow_interval": 1.0}
    assert [p.field_key for p in plc.interval_problems(SMART, given)] == ["slow_below_normal"]
    assert [p.field_key for p in plc.interval_problems(SMART, {"scan_interval": 1e6})] == [
        "interval_out_of_range"
    ]


def test_expose_problems_and_sending_off() -> None:
    """An expose its form refuses is named on its field; the others are made sending off."""
    quick = ConfigSubentryData(**{**EXPOSE, "data": {**EXPOSE["data"], "cooldown": 0.0}})
    (problem,) = PlcConfig.from_entry(entry([quick])).problems(SMART)
    assert problem.path[-1] == "cooldown"
    assert problem.key == "config_expose_cooldown_too_short"
    (made,) = PlcConfig.from_entry(entry([EXPOSE])).sending_off(SMART)
    assert made["data"]["send"] is False


def test_poll_minimums_count_each_point_once() -> None:
    """The points a poll reads are counted once, however many entities show them."""
    twice = [
        point("a", "A", "sensor", "VW10", "signed"),
        point("b", "B", "sensor", "VW10", "signed"),
    ]
    minimums, points = PlcConfig.from_entry(entry([device(twice)])).poll_minimums(SMART)
    assert len(points) == 1
    assert minimums["normal"] > 0


def test_options_keep_what_they_do_not_know() -> None:
    """Options besides the intervals are kept as they are."""
    options = PollOptions.from_options({"scan_interval": 5, "other": "x"})
    assert options.to_options() == {"scan_interval": 5, "other": "x"}
    assert options.intervals == {"scan_interval": 5.0}
    assert CONF_MAC not in Connection.from_data(DATA).to_data()
