"""Exceptions raised by the protocol layer: one base, one class per way a PLC call can fail."""

from __future__ import annotations


class PlcError(Exception):
    """Base of every error the protocol layer raises."""


class PlcConnectionError(PlcError):
    """The PLC could not be reached, or the link broke mid-request."""


class PlcTimeoutError(PlcConnectionError):
    """The PLC did not answer in time."""


class PlcSessionRefusedError(PlcConnectionError):
    """The PLC took the connection but refused the session asked for (a wrong slot or TSAP)."""


class PlcTlsError(PlcConnectionError):
    """TLS failed: untrusted certificate, or not the certificate pinned at setup."""


class PlcAuthenticationError(PlcError):
    """The PLC refused the credentials (or they stopped working)."""


class PlcAddressError(PlcError):
    """An address or variable name is invalid, unknown to the PLC, or its value does not fit."""


class PlcValueError(PlcError, ValueError):
    """A value does not fit the point's type or range; nothing was sent."""


class PlcWriteRefusedError(PlcError):
    """The PLC refused a write: CPU in STOP, no write permission, read-only point."""


class PlcProtocolError(PlcError):
    """The PLC answered something the protocol does not allow (malformed or unexpected reply)."""


class PlcOptionError(PlcValueError):
    """A vendor option cannot be used (a client certificate, a key); nothing was sent.

    `option` names the option at fault (the form field that shows it); `outside`: it names a
    file outside the folder the caller allows.
    """

    def __init__(self, message: str, option: str, *, outside: bool = False) -> None:
        """Keep which option is at fault, and whether it is a file outside the allowed folder."""
        super().__init__(message)
        self.option = option
        self.outside = outside
