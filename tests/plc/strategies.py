"""Hypothesis strategies and settings of every property test, in one place.

The property tests are bounded (a fixed number of examples, no deadline, derandomized) so that
a run of the suite stays quick and steady.
"""

from __future__ import annotations

from datetime import UTC
from zoneinfo import ZoneInfo

from hypothesis import HealthCheck, settings, strategies as st

BOUNDED = settings(
    max_examples=150,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
    derandomize=True,
    database=None,
)
ZONE = ZoneInfo("Europe/Prague")

JSON = st.recursive(
    st.none()
    | st.booleans()
    | st.integers(min_value=-(10**30), max_value=10**30)
    | st.floats(allow_nan=True, allow_infinity=True)
    | st.text(max_size=30),
    lambda inner: (
        st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=8), inner, max_size=4)
    ),
    max_leaves=10,
)
"""Any JSON value a PLC may answer, nested a little."""

VALUES = (
    st.none()
    | st.booleans()
    | st.integers()
    | st.floats()
    | st.text(max_size=40)
    | st.datetimes(timezones=st.just(UTC) | st.none())
    | st.lists(st.integers(), max_size=5)
)
"""Any value a user or an automation may ask to write."""

HEX_WORDS = st.from_regex(r"[+-]?0[xX][0-9a-fA-F]{0,10}", fullmatch=True)
"""Words written as hex text (SoftPLC takes them)."""

ADDRESSES = st.text(max_size=40) | st.from_regex(
    r"(V|VB|VW|VD|M|MW|I|Q|SMB|AIW|T|C|HC|DB[0-9]{0,6}\.DB[XBWD]|arr)[0-9٣]{0,12}(\.[0-9]{0,3})?"
    r"|[A-Za-z_][A-Za-z0-9_.\[\], ]{0,30}",
    fullmatch=True,
)
"""Addresses of S7-200 SMART, S7 and TecoApi, near-misses and any text."""

PLCNEXT_ADDRESSES = st.text(max_size=40) | st.from_regex(
    r"([A-Za-z.]{0,12}/)?[A-Za-z_][A-Za-z0-9_.\[\] ;/-]{0,30}", fullmatch=True
)
"""PLCnext variable paths (with or without a component), near-misses and any text."""

SOFTPLC_ADDRESSES = st.text(max_size=30) | st.from_regex(
    r"(PD|[OISBTCRNFX]|timer)[0-9٣]{0,7}(:[0-9]{0,7})?(\.[A-Za-z0-9]{0,4})?(/[0-9]{0,8})?",
    fullmatch=True,
)
"""SoftPLC data table addresses, near-misses and any text."""

SOFTPLC_REPLIES = st.binary(max_size=300) | st.from_regex(
    r"<files>(<data ad=\"[^\"]{0,12}\"( count=\"-?[0-9a-z]{0,4}\")?>"
    r"[^<]{0,20}</data>){0,3}</files>",
    fullmatch=True,
).map(str.encode)
"""SoftPLC reply bodies: any bytes, and documents of the reply's shape."""
