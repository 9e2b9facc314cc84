"""A Tecomat Foxtrot / TC700 TecoApi simulator."""

from .server import DEFAULT_PASSWORD, DEFAULT_USER, TecomatSimulator

__all__ = ["DEFAULT_PASSWORD", "DEFAULT_USER", "TecomatSimulator"]
