"""A Siemens S7 CPU on python-snap7's server; READINGS.md lists the readings it can answer."""

from .cpu import S7Simulator

__all__ = ["S7Simulator"]
