"""Turn protocol errors of writes, reads and clock calls into translated Home Assistant errors."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

from homeassistant.config_entries import ConfigEntry
from homeassistant.core import HomeAssistant
from homeassistant.exceptions import (
    HomeAssistantError,
    ServiceValidationError,
)

from ..const import DOMAIN
from ..plc import (
    PlcAddressError,
    PlcAuthenticationError,
    PlcError,
    PlcValueError,
    PlcWriteRefusedError,
    Point,
)


def plc_error(key: str, err: PlcError | str) -> HomeAssistantError:
    """Return a translated error whose message carries the protocol layer's explanation."""
    return HomeAssistantError(
        translation_domain=DOMAIN,
        translation_key=key,
        translation_placeholders={"error": str(err)},
    )


def invalid(key: str, err: PlcError | str) -> ServiceValidationError:
    """Return a translated error about what the user asked for; nothing was sent."""
    return ServiceValidationError(
        translation_domain=DOMAIN,
        translation_key=key,
        translation_placeholders={"error": str(err)},
    )


@contextmanager
def translated_errors(hass: HomeAssistant, entry: ConfigEntry[Any]) -> Iterator[None]:
    """Raise the translated Home Assistant error for a protocol error of an action or a write."""
    try:
        yield
    except PlcValueError as err:
        raise invalid("invalid_value", err) from err
    except PlcAddressError as err:
        raise invalid("invalid_address", err) from err
    except PlcWriteRefusedError as err:
        raise plc_error("write_refused", err) from err
    except PlcAuthenticationError as err:
        entry.async_start_reauth(hass)
        raise plc_error("invalid_auth", err) from err
    except PlcError as err:
        raise plc_error("communication_error", err) from err


def check_can_write(entry: ConfigEntry[Any]) -> None:
    """Refuse a write before sending when the PLC said at connect time that its user may not."""
    if not entry.runtime_data.device.can_write:
        raise ServiceValidationError(
            translation_domain=DOMAIN,
            translation_key="no_write_permission",
            translation_placeholders={"title": entry.title},
        )


def named(point: Point, error: PlcError) -> str:
    """Return a point's error led by its address, unless the vendor's words already are."""
    text = str(error)
    return text if text.startswith(f"{point.address}:") else f"{point.address}: {text}"
