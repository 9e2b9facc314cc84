"""A Siemens S7-200 SMART Web API simulator: JSON-RPC 2.0 on POST /Web_api over HTTPS."""

from .errors import CODES, ERRORS
from .memory import Memory
from .server import DEFAULT_PASSWORD, DEFAULT_USER, HttpFault, S7SmartSimulator

__all__ = [
    "CODES",
    "DEFAULT_PASSWORD",
    "DEFAULT_USER",
    "ERRORS",
    "HttpFault",
    "Memory",
    "S7SmartSimulator",
]
