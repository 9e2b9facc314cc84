"""SoftPLC runtimes through the WEB.TLM REST server (XML): datatable addresses and tags."""

from .client import SoftplcClient

CLIENT = SoftplcClient

__all__ = ["CLIENT", "SoftplcClient"]
