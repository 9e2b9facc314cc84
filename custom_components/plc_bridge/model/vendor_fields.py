"""What each vendor's connection asks besides host and port: its fields and second pages.

The connection forms show them; the pasted PLC file may carry exactly these keys.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from homeassistant.helpers.selector import (
    NumberSelector,
    NumberSelectorConfig,
    NumberSelectorMode,
    Selector,
    SelectSelector,
    SelectSelectorConfig,
    SelectSelectorMode,
    TextSelector,
    TextSelectorConfig,
)

from ..plc.vendors.logo.address import GENERATIONS
from ..plc.vendors.logo.options import DEFAULT_TSAPS


@dataclass(frozen=True, slots=True)
class VendorField:
    """A vendor-only field of the connection form, kept in entry.data["vendor_options"]."""

    key: str
    selector: Selector[Any]
    default: str | int | bool | None = None  # None: an optional field
    credential: bool = False  # a secret: never suggested again, kept when left empty


@dataclass(frozen=True, slots=True)
class SecondPage:
    """Fields asked on a page of their own, by the way a field of the first page chose."""

    choice: str  # the first page's field that chooses
    ways: Mapping[str, tuple[VendorField, ...]]  # its values: the first one is the default
    refused_on: Mapping[str, str]  # per way, the field blamed when the PLC refuses the session


def choice(key: str, options: list[str]) -> SelectSelector:
    """Return a translated select of fixed options."""
    return SelectSelector(
        SelectSelectorConfig(options=options, translation_key=key, mode=SelectSelectorMode.LIST)
    )


def _whole(low: int, high: int) -> NumberSelector:
    """Return a whole-number box."""
    return NumberSelector(
        NumberSelectorConfig(min=low, max=high, step=1, mode=NumberSelectorMode.BOX)
    )


VENDOR_FIELDS: dict[str, tuple[VendorField, ...]] = {
    "tecomat": (
        VendorField("auth", choice("auth", ["digest", "basic"]), "digest"),
        VendorField("clock_variable", TextSelector()),
    ),
    "plcnext": (VendorField("clock_variable", TextSelector()),),
    "softplc": (
        VendorField(
            "client_certificate",
            TextSelector(TextSelectorConfig(multiline=True)),
            credential=True,
        ),
        VendorField(
            "client_key", TextSelector(TextSelectorConfig(multiline=True)), credential=True
        ),
    ),
    "s7": (
        VendorField("family", choice("family", ["s7_300_1500", "s7_200"]), "s7_300_1500"),
        VendorField("connection", choice("connection", ["rack_slot", "tsap"]), "rack_slot"),
    ),
    "logo": (VendorField("generation", choice("generation", list(GENERATIONS)), "0ba8"),),
}
"""Extra fields of a vendor's connection page, shown after the credentials.

Whole numbers come back as int; the client checks them (`validate_options`) and reads them
from ConnectionConfig.options.
"""


SECOND_PAGES: dict[str, SecondPage] = {
    "s7": SecondPage(
        "connection",
        {
            "rack_slot": (
                VendorField("rack", _whole(0, 7), 0),
                VendorField("slot", _whole(0, 31), 1),
            ),
            "tsap": (
                VendorField("local_tsap", TextSelector()),
                VendorField("remote_tsap", TextSelector()),
            ),
        },
        {"rack_slot": "slot", "tsap": "remote_tsap"},
    ),
    "logo": SecondPage(
        "generation",
        {
            generation: (
                VendorField("local_tsap", TextSelector(), local),
                VendorField("remote_tsap", TextSelector(), remote),
            )
            for generation, (local, remote) in DEFAULT_TSAPS.items()
        },
        dict.fromkeys(DEFAULT_TSAPS, "remote_tsap"),
    ),
}
"""Vendors whose connection takes a second page: only the fields of the way chosen are asked."""
