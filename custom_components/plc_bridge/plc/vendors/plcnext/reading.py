"""PLCnext reads: one registered group per poll, variable reads where groups cannot serve.

Polls that alternate between point sets (poll classes) keep a group for each (GROUPS_KEPT).

Unknown names are found by reading halves (a register or read naming one answers 404 as a
whole, PyREST's real-device log: `invalidNames`) and left out of the group; they are tried
again when the program changes (`projectCRC`) or the points do. Where every name is unknown, a
groups report (one request that carries `projectCRC`) watches the program instead of a group read.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
import json
from typing import Any
from urllib.parse import quote, urlencode

from ...errors import PlcAddressError, PlcError, PlcProtocolError
from .api import PlcnextApi, Request
from .errors import ApiError, request_error
from .groups import GROUPS_KEPT, Group, registered
from .paths import MAX_URI, VariablePath, path_list, same_path, variables_uri
from .placing import Reading, isolate, place

JSON = "application/json"
FORM = "application/x-www-form-urlencoded"
REFUSED_BODY = (400, 415)  # a register body the PLC does not parse: try the other form once
NO_GROUPS = (400, 405, 415, 501)  # groups cannot serve: read variables instead


GROUP_POLLS_UP_TO = 90.0
"""The longest poll interval read through a group: a late poll still finds it. Beyond, every
poll would find it gone and register it again (three requests): variable reads take one."""


class Reader:
    """Keeps the poll's group, the names the PLC lacks and what the groups can do."""

    def __init__(self, api: PlcnextApi, poll_interval: float = 0.0) -> None:
        """Start with no group; groups are tried first, with a JSON body, where they last."""
        self._api = api
        self.use_groups = poll_interval <= GROUP_POLLS_UP_TO
        self.group: Group | None = None  # the last poll's
        self._kept: dict[tuple[VariablePath, ...], Group] = {}  # others, oldest first
        self._recent: dict[frozenset[str], None] = {}  # the last polls' path sets
        self.unknown: dict[str, PlcError] = {}
        self.groups_ok = True
        self.form_body = False  # the Groups page's form body instead of the clients' JSON
        self.crc: Any = None  # the program the last answer was made for
        self.regroups = 0  # groups registered again after the PLC lost one (diagnostics)

    async def poll(self, paths: dict[str, VariablePath], *, again: bool = False) -> Reading:
        """Read the poll's paths in one request (a group read) where nothing changed.

        A projectCRC other than the last one (a program downloaded again) drops the group and
        the unknown names, and reads once more with a group registered for the new program.
        """
        self._recent.pop(asked := frozenset(paths), None)
        self._recent[asked] = None
        while len(self._recent) > GROUPS_KEPT:
            del self._recent[next(iter(self._recent))]
        if self.unknown:  # a name no recent poll asks is tried again once asked
            recent = frozenset().union(*self._recent)
            self.unknown = {key: err for key, err in self.unknown.items() if key in recent}
        unknown = self.unknown
        wanted = (
            [p for key, p in paths.items() if key not in unknown] if unknown else [*paths.values()]
        )
        if self.groups_ok and self.use_groups:
            reading = await self._group_read(wanted)
        else:
            reading = await self.variables(wanted, self.unknown)
        if self.unknown and reading.crc is None:  # nothing read: watch the program for them
            reading.crc = await self._project_crc()
        changed = reading.crc is not None and self.crc is not None and reading.crc != self.crc
        if reading.crc is not None:
            self.crc = reading.crc
        fresh = self.group is not None and self.group.crc == reading.crc
        if changed and not again and (self.unknown or not fresh):
            await self.unregister_group()
            self.unknown = {}
            return await self.poll(paths, again=True)
        reading.failed.update(self.unknown)
        return reading

    async def _group_read(self, wanted: list[VariablePath]) -> Reading:
        """Read the group of these paths, registering it where the PLC has none."""
        reading = Reading()
        if self.group is None or self.group.paths != tuple(wanted):
            await self._switch(tuple(wanted))
        if self.group is None:
            await self._register(wanted)
            if not self.groups_ok:
                return await self.variables(wanted, self.unknown)
        group = self.group
        if group is None or not group.paths:
            return reading
        try:
            answer = await self._api.call("GET", self._group_uri(group.id))
        except ApiError as err:
            if err.status != 404:
                raise request_error(err) from None
            # The PLC no longer knows the group (120 s idle, restart, new program).
            self.regroups += 1
            await self._register(wanted)
            if not self.groups_ok:
                return await self.variables(wanted, self.unknown)
            group = self.group
            if group is None or not group.paths:
                return reading
            try:
                answer = await self._api.call("GET", self._group_uri(group.id))
            except ApiError as again:
                raise request_error(again) from None
        if isinstance(answer, dict) and answer.get("id") not in (None, group.id):
            raise PlcProtocolError(f"the PLC answered group {answer.get('id')!r}, not {group.id}")
        place(answer, group.paths, reading, group.names)
        return reading

    async def _switch(self, wanted: tuple[VariablePath, ...]) -> None:
        """Keep the last poll's group and take the one kept for these paths (None: none yet).

        The oldest kept group is unregistered beyond GROUPS_KEPT.
        """
        if self.group is not None and self.group.paths:
            self._kept.pop(self.group.paths, None)
            self._kept[self.group.paths] = self.group
        self.group = self._kept.pop(wanted, None)
        while len(self._kept) >= GROUPS_KEPT:
            oldest = self._kept.pop(next(iter(self._kept)))
            if oldest.id and oldest.created:
                await self.unregister(oldest.id)

    async def _project_crc(self) -> Any:
        """Return the projectCRC of a groups report (Groups page); None where it has none."""
        try:
            answer = await self._api.call(
                "GET", lambda _session: (f"{self._api.base}/groups", None, None)
            )
        except ApiError:
            return None
        return answer.get("projectCRC") if isinstance(answer, dict) else None

    def _group_uri(self, group_id: str) -> Callable[[str | None], Request]:
        """Return the request maker of a group's read or unregistration (with the session)."""

        def make(session: str | None) -> Request:
            query = f"?sessionID={quote(session, safe='')}" if session else ""
            return f"{self._api.base}/groups/{quote(group_id, safe='')}{query}", None, None

        return make

    async def _register(self, wanted: list[VariablePath]) -> None:
        """Register a group of the paths the PLC knows; learn the unknown ones by reading.

        A register naming an unknown path answers 404 as a whole: the names are then found
        with variable reads, which leave nothing behind on the PLC, and one group registered.
        """
        self.group = None
        known: list[VariablePath] = wanted
        try:
            try:
                answer = await self._register_once(wanted) if wanted else None
            except ApiError as err:
                if err.status != 404:
                    raise
                known = await self._known(wanted)
                answer = await self._register_once(known) if known else None
        except ApiError as err:
            if err.status in NO_GROUPS or err.status == 404:  # 404: groups refuse what reads take
                self.groups_ok = False
                return
            raise request_error(err) from None
        if not known:
            self.group = Group("", (), self.crc)
            return
        group_id = answer.get("id") if isinstance(answer, dict) else None
        if not isinstance(group_id, str) or not group_id:
            raise PlcProtocolError("the PLC registered the group but sent no id")
        assert isinstance(answer, dict)
        created = self._api.last_status == 201
        names = registered(known)[1]
        self.group = Group(group_id, tuple(known), answer.get("projectCRC"), created, names)

    async def _known(self, wanted: list[VariablePath]) -> list[VariablePath]:
        """Return the paths the PLC knows, learning the others by variable reads.

        One read answers where the PLC fails unknown names per entry; where it refuses the
        whole read (404), halves find them.
        """
        known, answer = await isolate(wanted, self._read_once, self.unknown)
        if answer is not None:
            reading = Reading()
            place(answer, known, reading)
            for key, err in reading.failed.items():
                if isinstance(err, PlcAddressError):
                    self.unknown[key] = err
        return [path for path in known if path.key not in self.unknown]

    async def unregister_group(self) -> None:
        """Unregister the poll's groups (best effort: they expire on their own)."""
        groups = [self.group, *self._kept.values()]
        self.group, self._kept = None, {}
        for group in groups:
            if group is not None and group.id and group.created:
                await self.unregister(group.id)

    async def unregister(self, group_id: str) -> None:
        """DELETE a group (best effort: the PLC drops it after about 120 s unused)."""
        try:
            await self._api.call("DELETE", self._group_uri(group_id))
        except ApiError:
            return

    async def types_of(self, paths: Sequence[VariablePath]) -> dict[str, str]:
        """Return the IEC type names a register answer gives for paths, by path key.

        The group is unregistered at once, unless the PLC reused an identical one (200).
        """
        if not paths or not self.groups_ok:
            return {}
        try:
            answer = await self._register_once(paths)
        except ApiError:
            return {}
        created = self._api.last_status == 201
        group_id = answer.get("id") if isinstance(answer, dict) else None
        if created and isinstance(group_id, str) and group_id:
            await self.unregister(group_id)
        entries = answer.get("variables") if isinstance(answer, dict) else None
        if not isinstance(entries, list) or len(entries) != len(paths):
            return {}
        return {
            path.key: entry["type"]
            for path, entry in zip(paths, entries, strict=True)
            if isinstance(entry, dict)
            and isinstance(entry.get("type"), str)
            and same_path(entry.get("path", path.text), path)
        }

    async def _register_once(self, paths: Sequence[VariablePath]) -> Any:
        """POST /groups once; a body the PLC cannot parse is sent once in the other form.

        The Groups page describes a form body and shows a JSON one in its example; pyPLCn and
        PyREST send JSON. JSON first, the form where the PLC refuses it (kept from then on).
        """
        for form in (self.form_body, not self.form_body):
            try:
                answer = await self._api.call("POST", self._register_request(paths, form=form))
            except ApiError as err:
                if err.status not in REFUSED_BODY or form != self.form_body:
                    raise
                continue
            self.form_body = form
            return answer
        raise AssertionError("not reached")  # pragma: no cover

    def _register_request(
        self, paths: Sequence[VariablePath], *, form: bool
    ) -> Callable[[str | None], Request]:
        """Return the request maker of a group registration (see `registered`)."""
        base = self._api.base
        prefix, names = registered(paths)

        def make(session: str | None) -> Request:
            if form:
                fields = {"sessionID": session or "", "pathPrefix": prefix}
                body = f"{urlencode(fields)}&paths={path_list(names)}"
                return f"{base}/groups", body.encode(), FORM
            data = {"sessionID": session or "", "pathPrefix": prefix, "paths": names}
            return f"{base}/groups", json.dumps(data).encode(), JSON

        return make

    async def variables(
        self, paths: Sequence[VariablePath], unknown: dict[str, PlcError]
    ) -> Reading:
        """Read variables directly: GET for a short list, POST for a long one."""
        reading = Reading()
        try:
            known, answer = await isolate(paths, self._read_once, unknown)
            if known and answer is None:
                answer = await self._read_once(known)
        except ApiError as err:
            raise request_error(err) from None
        if known:
            place(answer, known, reading)
        reading.failed.update(
            {key: err for key, err in unknown.items() if key not in reading.found}
        )
        return reading

    async def _read_once(self, paths: Sequence[VariablePath]) -> Any:
        """Read the paths with one GET /variables, or one POST where the URI would be long."""
        base = self._api.base
        long = len(variables_uri(base, paths, None)) > MAX_URI - 64  # room for a session id

        def make(session: str | None) -> Request:
            if not long:
                return variables_uri(base, paths, session), None, None
            fields = {"paths": ",".join(path.text for path in paths)}
            if session:
                fields = {"sessionID": session, **fields}
            return f"{base}/variables", urlencode(fields).encode(), FORM

        return await self._api.call("POST" if long else "GET", make, idempotent=True)
