"""S7 connection options that cannot be used end in PlcOptionError naming their field."""

from __future__ import annotations

from typing import Any

import pytest

from custom_components.plc_bridge.plc import ConnectionConfig, PlcOptionError
from custom_components.plc_bridge.plc.vendors.s7 import S7Client

HUGE = "9" * 5000  # more digits than int() takes from text


@pytest.mark.parametrize(
    ("options", "field"),
    [
        ({"rack": "²"}, "rack"),  # str.isdigit() says yes, int() says no
        ({"rack": "٣"}, "rack"),  # an Arabic-Indic three
        ({"slot": HUGE}, "slot"),
        ({"slot": 10**5000}, "slot"),
        ({"slot": float("inf")}, "slot"),
        ({"slot": float("nan")}, "slot"),
        ({"slot": 1e300}, "slot"),
        ({"slot": [1]}, "slot"),
        ({"connection": "tsap", "remote_tsap": HUGE}, "remote_tsap"),
        ({"connection": "tsap", "remote_tsap": "²².01"}, "remote_tsap"),
        ({"connection": "tsap", "remote_tsap": "10.01", "local_tsap": 1.5}, "local_tsap"),
        ({"connection": "tsap"}, "remote_tsap"),
        ({"connection": HUGE}, "connection"),
        ({"family": {"s7_200"}}, "family"),
    ],
)
def test_bad_options_name_their_field(options: dict[str, Any], field: str) -> None:
    with pytest.raises(PlcOptionError) as caught:
        S7Client.validate_options(options)
    assert caught.value.option == field
    assert len(str(caught.value)) < 120  # a 5,000-digit value is not repeated whole


def test_at_construction() -> None:
    config = ConnectionConfig(host="plc", port=102, options={"rack": "²", "slot": 1})
    with pytest.raises(PlcOptionError, match="rack must be a whole number") as caught:
        S7Client(config)
    assert caught.value.option == "rack"


@pytest.mark.parametrize(
    ("options", "rack", "slot"),
    [({"rack": " 1 ", "slot": "03"}, 1, 3), ({"rack": 2.0, "slot": 31}, 2, 31)],
)
def test_numbers_from_forms(options: dict[str, Any], rack: int, slot: int) -> None:
    found = S7Client.validate_options(options)
    assert (found["rack"], found["slot"]) == (rack, slot)
