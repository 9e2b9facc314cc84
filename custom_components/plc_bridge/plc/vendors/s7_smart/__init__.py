"""Siemens S7-200 SMART through its Web API (CPU firmware 2.7 or later)."""

from .client import S7SmartClient

CLIENT = S7SmartClient

__all__ = ["CLIENT", "S7SmartClient"]
