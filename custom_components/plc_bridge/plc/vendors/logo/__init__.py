"""Siemens LOGO! 0BA7, 0BA8 and 8.x on the S7 transport, addressed as LOGO!Soft Comfort does."""

from .client import LogoClient
from .probe import answers

CLIENT = LogoClient
PROBE = answers

__all__ = ["CLIENT", "PROBE", "LogoClient", "answers"]
