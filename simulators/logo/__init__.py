"""A Siemens LOGO! on the S7 simulator; READINGS.md lists the readings it can answer."""

from .simulator import LogoSimulator

__all__ = ["LogoSimulator"]
