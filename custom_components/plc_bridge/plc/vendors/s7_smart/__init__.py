"""Siemens S7-200 SMART through its Web API (CPU firmware 2.7 or later)."""

from .client import S7SmartClient
from .probe import answers

CLIENT = S7SmartClient
PROBE = answers

__all__ = ["CLIENT", "PROBE", "S7SmartClient", "answers"]
