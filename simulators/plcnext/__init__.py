"""A Phoenix Contact PLCnext REST data interface simulator."""

from .server import (
    DEFAULT_PASSWORD,
    DEFAULT_USER,
    NO_ROLE_USER,
    VIEWER_USER,
    PlcnextSimulator,
)

__all__ = [
    "DEFAULT_PASSWORD",
    "DEFAULT_USER",
    "NO_ROLE_USER",
    "VIEWER_USER",
    "PlcnextSimulator",
]
