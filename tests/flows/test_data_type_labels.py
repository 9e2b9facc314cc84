"""Data types shown by their labels in every form: a field that also takes a typed value shows
the raw key once chosen (the frontend's picker has no label for it), so only families whose types
take parameters (STRING[20]) get one; the S7-200 SMART's modes are chosen by their labels."""

from __future__ import annotations

from typing import Any

from homeassistant.helpers.selector import SelectSelector
import pytest

from custom_components.plc_bridge.const import CONF_DATA_TYPE
from custom_components.plc_bridge.flows.composite_flow import data_types
from custom_components.plc_bridge.flows.expose_flow import expose_schema
from custom_components.plc_bridge.flows.point_form import base_schema
from custom_components.plc_bridge.model.availability import (
    CONF_AVAILABILITY_DATA_TYPE,
    availability_fields,
)
from custom_components.plc_bridge.plc.vendors import client_class, implemented
from tests.flows.forms import strings_at


def field(schema: Any, key: str) -> SelectSelector:
    """Return a form's selector of a key."""
    fields = schema.schema if hasattr(schema, "schema") else schema
    (selector,) = [value for marker, value in fields.items() if str(marker) == key]
    assert isinstance(selector, SelectSelector)
    return selector


def selectors(vendor: str) -> list[SelectSelector]:
    """Return the data type field of each form: point, part, expose, machine availability."""
    client = client_class(vendor)
    return [
        field(base_schema(client), CONF_DATA_TYPE),
        data_types(client),
        field(expose_schema(client, "sensor.outdoor", attribute=True), CONF_DATA_TYPE),
        field(availability_fields(client), CONF_AVAILABILITY_DATA_TYPE),
    ]


@pytest.mark.parametrize("vendor", implemented())
def test_data_types_by_their_labels(vendor: str) -> None:
    """Every form offers the family's types with their labels; typed ones only where needed."""
    client = client_class(vendor)
    for selector in selectors(vendor):
        assert selector.config["translation_key"] == CONF_DATA_TYPE
        assert selector.config["options"] == list(client.data_types)
        assert selector.config["custom_value"] is client.typed_data_types


def test_labelled_family_chooses_from_its_labels() -> None:
    """The S7-200 SMART's modes all have labels, and are chosen only by them."""
    labels = strings_at("selector", CONF_DATA_TYPE, "options")
    client = client_class("s7_smart")
    assert set(client.data_types) <= set(labels)
    assert not client.typed_data_types
    assert client_class("s7").typed_data_types  # STRING[20]
