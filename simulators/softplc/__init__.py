"""A SoftPLC WEB.TLM (REST, XML) simulator."""

from .server import DEFAULT_TAGS, SoftplcSimulator

__all__ = ["DEFAULT_TAGS", "SoftplcSimulator"]
