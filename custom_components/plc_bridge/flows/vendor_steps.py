"""The step ids of the vendors' pages, each bound to the config flow's shared step behind it.

Home Assistant finds a step by its id (`async_step_<id>`), and strings.json words each page for
its PLC family alone (`connection_s7`, `reconfigure_s7`, `s7_tsap`, `reauth_softplc`): every
such id is bound here, for every implemented vendor, to `_connection_step`, `_second_page_step`
or `_reauth_options`.
"""

from __future__ import annotations

from typing import Any

from homeassistant.config_entries import ConfigFlow

from ..model.vendor_fields import SECOND_PAGES
from ..plc.vendors import client_class, implemented
from .connection_form import connection_step, second_page

type Input = dict[str, Any] | None
"""What a form step receives: the submitted values, or None to show the form."""


def vendor_pages(vendor: str) -> dict[str, str]:
    """Return the step ids of a vendor's pages and the name of the shared step taking each."""
    pages = {
        connection_step(vendor, reconfigure=reconfigure): "_connection_step"
        for reconfigure in (False, True)
    }
    if (page := SECOND_PAGES.get(vendor)) is not None:
        for way in page.ways:
            pages[second_page(vendor, {page.choice: way})[0]] = "_second_page_step"
    if client_class(vendor).credential_option is not None:
        pages[f"reauth_{vendor}"] = "_reauth_options"
    return pages


def with_vendor_steps[F: type[ConfigFlow]](flow: F) -> F:
    """Give the flow a step for each page of each implemented vendor; return it."""
    for vendor in implemented():
        for step_id, shared in vendor_pages(vendor).items():
            setattr(flow, f"async_step_{step_id}", getattr(flow, shared))
    return flow
