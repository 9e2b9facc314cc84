"""Tecomat Foxtrot and TC700 through the TecoApi of their web server (firmware 10.4 or later)."""

from .client import TecomatClient
from .probe import answers

CLIENT = TecomatClient
PROBE = answers

__all__ = ["CLIENT", "PROBE", "TecomatClient", "answers"]
