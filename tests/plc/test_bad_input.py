"""Any input ends in the project's own errors, with a message for the form (issue 10)."""

from __future__ import annotations

from datetime import datetime, timedelta, timezone

import pytest

from custom_components.plc_bridge.plc import ConnectionConfig, PlcAddressError, PlcValueError, Point
from custom_components.plc_bridge.plc.codec import check_float, check_integer
from custom_components.plc_bridge.plc.vendors import client_class

pytestmark = pytest.mark.no_pacing

HUGE = "9" * 5000  # int() refuses more than 4,300 digits with a bare ValueError


@pytest.mark.parametrize(
    ("vendor", "point"),
    [
        ("s7_smart", Point(f"VW{HUGE}", "signed")),
        ("s7_smart", Point("VW١٠", "signed")),  # Arabic-Indic digits are no PLC address
        ("s7", Point(f"DB{HUGE}.DBW0", "INT")),
        ("s7", Point("DB٣.DBW0", "INT")),
        ("s7", Point("DB1.DBB0", f"STRING[{HUGE}]")),
        ("tecomat", Point(f"arr[{HUGE}]", "INT")),
    ],
)
def test_addresses_refused_cleanly(vendor: str, point: Point) -> None:
    """Huge numbers and non-ASCII digits are refused as addresses, never a bare ValueError."""
    with pytest.raises(PlcAddressError):
        client_class(vendor).validate_point(point)


def test_values_refused_cleanly() -> None:
    """A whole number of 5,000 digits and 10**400 as a REAL are refused as values."""
    with pytest.raises(PlcValueError):
        check_integer(HUGE, 0, 255)
    with pytest.raises(PlcValueError):
        check_integer("٣", 0, 255)
    with pytest.raises(PlcValueError):
        check_float(10**400)


@pytest.mark.parametrize("vendor", ["s7_smart", "s7", "tecomat"])
@pytest.mark.parametrize(
    "when",
    [
        datetime(1, 1, 1, tzinfo=timezone(timedelta(hours=5))),
        datetime(9999, 12, 31, 23, tzinfo=timezone(timedelta(hours=-5))),
    ],
)
async def test_clock_beyond_the_calendar_refused(vendor: str, when: datetime) -> None:
    """An aware time with no local time in the PLC's zone is a value error, before sending."""
    options: dict[str, str | int | bool] = (
        {"clock_variable": "setTime"} if vendor == "tecomat" else {}
    )
    config = ConnectionConfig(host="127.0.0.1", port=9, time_zone="UTC", options=options)
    client = client_class(vendor)(config)
    with pytest.raises(PlcValueError):
        await client.set_clock(when)
