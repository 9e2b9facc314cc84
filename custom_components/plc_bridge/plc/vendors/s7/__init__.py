"""Siemens S7 (S7-200 with CP 243-1, S7-300/400, S7-1200/1500) over S7comm on ISO-on-TCP."""

from .client import S7Client
from .probe import answers

CLIENT = S7Client
PROBE = answers

__all__ = ["CLIENT", "PROBE", "S7Client", "answers"]
