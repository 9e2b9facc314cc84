"""SoftPLC runtimes through the WEB.TLM REST server (XML): datatable addresses and tags."""

from .client import SoftplcClient
from .tls import MaterialError, resolve_material

CLIENT = SoftplcClient

__all__ = ["CLIENT", "MaterialError", "SoftplcClient", "resolve_material"]
