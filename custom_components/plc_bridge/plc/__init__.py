"""PLC Bridge protocol layer: vendor-neutral clients for PLC network interfaces.

Never imports Home Assistant; takes an injected `aiohttp.ClientSession` where the vendor is HTTP.
"""

from .client import PlcClient, ResultsCallback
from .errors import (
    PlcAddressError,
    PlcAuthenticationError,
    PlcConnectionError,
    PlcError,
    PlcOptionError,
    PlcProtocolError,
    PlcSessionRefusedError,
    PlcTimeoutError,
    PlcTlsError,
    PlcValueError,
    PlcWriteRefusedError,
)
from .http import urgent
from .types import (
    BrowseItem,
    ClientMetrics,
    ConnectionConfig,
    DeviceInfo,
    Footprint,
    PlcStatus,
    Point,
    PointResult,
    ReadResult,
    TlsMode,
    Value,
    ValueKind,
)

__all__ = [
    "BrowseItem",
    "ClientMetrics",
    "ConnectionConfig",
    "DeviceInfo",
    "Footprint",
    "PlcAddressError",
    "PlcAuthenticationError",
    "PlcClient",
    "PlcConnectionError",
    "PlcError",
    "PlcOptionError",
    "PlcProtocolError",
    "PlcSessionRefusedError",
    "PlcStatus",
    "PlcTimeoutError",
    "PlcTlsError",
    "PlcValueError",
    "PlcWriteRefusedError",
    "Point",
    "PointResult",
    "ReadResult",
    "ResultsCallback",
    "TlsMode",
    "Value",
    "ValueKind",
    "urgent",
]
