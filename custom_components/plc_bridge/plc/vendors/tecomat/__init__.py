"""Tecomat Foxtrot and TC700 through the TecoApi of their web server (firmware 10.4 or later)."""

from .client import TecomatClient

CLIENT = TecomatClient

__all__ = ["CLIENT", "TecomatClient"]
