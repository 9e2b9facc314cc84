"""PLCnext writes: one `PUT /variables` of every value, per-variable results read by structure.

The variables doc answers a PUT with one entry per variable (`path`, `value`, `uri`); an entry
with an error, or with `value: null` (PyREST's reading), is a value the PLC did not take. A whole
refusal (403 read-only or not permitted, 404 an unknown name) of several variables is sent again
by halves, so that one bad variable does not fail the others.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
import json
from typing import Any

from ...errors import PlcAddressError, PlcError, PlcWriteRefusedError
from ...types import Point, PointResult
from .api import PlcnextApi, Request
from .errors import ApiError, request_error
from .paths import VariablePath
from .placing import Reading, place
from .reading import JSON

type Item = tuple[Point, VariablePath, Any]
"""A point, its parsed path and the JSON value the PUT carries."""


def put_request(base: str, items: Sequence[Item]) -> Callable[[str | None], Request]:
    """Return the request maker of one PUT of the items (its session id keeps the session)."""

    def make(session: str | None) -> Request:
        variables = [
            {"path": path.text, "value": value, "valueType": "Constant"}
            for _point, path, value in items
        ]
        body: dict[str, Any] = {"variables": variables}
        if session:
            body = {"sessionID": session, **body}
        return f"{base}/variables", json.dumps(body).encode(), JSON

    return make


async def put(api: PlcnextApi, items: Sequence[Item], results: dict[Point, PointResult]) -> None:
    """PUT the items; a whole refusal (403, 404) of several is sent again by halves."""
    if not items:
        return
    try:
        answer = await api.call("PUT", put_request(api.base, items))
    except ApiError as err:
        if err.status in (403, 404) and len(items) > 1:
            half = len(items) // 2
            await put(api, items[:half], results)
            await put(api, items[half:], results)
            return
        if err.status == 404:
            error: PlcError = PlcAddressError(
                f"{items[0][1].text}: the PLC does not know this variable ({err.words})"
            )
        else:
            error = request_error(err, write=True)
        if len(items) > 1 or err.status not in (403, 404):
            raise error from None
        results[items[0][0]] = PointResult(error=error)
        return
    taken(answer, items, results)


def taken(answer: Any, items: Sequence[Item], results: dict[Point, PointResult]) -> None:
    """Read a PUT's per-variable results: an error or a null value is a refused write."""
    entries = answer.get("variables") if isinstance(answer, dict) else None
    if not isinstance(entries, list):  # an answer without results: taken as written
        for point, _path, _value in items:
            results[point] = PointResult()
        return
    reading = Reading()
    place(answer, [path for _point, path, _value in items], reading)
    for point, path, _value in items:
        if path.key in reading.failed:
            said = reading.failed[path.key]
            results[point] = PointResult(
                error=PlcWriteRefusedError(f"the PLC refused the write: {said}")
            )
        elif reading.found.get(path.key) is None:
            results[point] = PointResult(
                error=PlcWriteRefusedError(f"{path.text}: the PLC did not take the value")
            )
        else:
            results[point] = PointResult()
