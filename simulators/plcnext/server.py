"""A PLCnext Control's REST data interface (../shared/specs/phoenix-plcnext-rest-*.{txt,md}).

Service description, two-step authentication, sessions, variables, groups and the eHMI
dictionaries, over HTTPS with a self-signed certificate. Where the sources disagree, switches
choose: `bodies` ("both", "json", "form" group registrations), `text_values` (values sent as
text), `trailing_slashes`, `groups.timeout`, `auth` (user authentication on or off),
`unknown_entries` (unknown names in a variable read fail their entry, not the request),
`groups_served` (False: an interface without groups), `program.case_sensitive` (names match
only as declared), `declared_spelling` (answers spell paths as declared, not as asked),
`station_conflicts` (409 for a second session of one station), `session_cap` (the longest
session timeout granted) and `session_answer` (the create answer names the timeout granted,
or it is "absent": the sessions report names it). See READINGS.md.
`foreign` answers the cases the sources leave open with other reasons and error shapes than
the client's tests assume, so the client is tested on structure.
"""

from __future__ import annotations

import math
import secrets
from typing import Any

from aiohttp import web

from ..base import HttpSimulator
from ..machines import run_machines
from .access import Access
from .demo import MACHINES, default_program
from .groups import Groups
from .parameters import Fault, body_fields, paths_of, query_fields
from .program import (
    PREFIX,
    Leaf,
    Program,
    Refused,
    Variable,
    as_json,
    node_type,
)
from .routes import AccessRoutes

DEFAULT_USER = "admin"
DEFAULT_PASSWORD = "PLCnext-1"
VIEWER_USER = "viewer"  # EHmiViewer only: may read, not write
NO_ROLE_USER = "guest"  # no EHmi role: may log in, not read (accessDenied)
API_VERSION = "1.8.0.0"
VERSIONS = ("api", "v1.0", "v1.1", "v1.2", "v1.3", "v1.4", "v1.5", "v1.6", "v1.7", "v1.8")


class PlcnextSimulator(AccessRoutes, HttpSimulator):
    """A PLCnext Control running the demo project (`demo.default_program`)."""

    tls = True
    common_name = "plcnext-axc-f-2152"

    def __init__(self, *, auth: bool = True, bench: int = 0, foreign: bool = False) -> None:
        super().__init__()
        self.auth = auth
        self.foreign = foreign
        self.access = Access(
            {
                DEFAULT_USER: (DEFAULT_PASSWORD, ["EHmiViewer", "EHmiChanger"]),
                VIEWER_USER: (DEFAULT_PASSWORD, ["EHmiViewer"]),
                NO_ROLE_USER: (DEFAULT_PASSWORD, []),
            }
        )
        self.program: Program = default_program(bench)
        self.crc = 2373751656
        self.bodies = "both"
        self.text_values = False
        self.trailing_slashes = True
        self.unknown_entries = False
        self.keep_groups = False  # groups survive a download (then stale names fail per entry)
        self.groups_served = True  # False: an interface without groups (405 on /groups)
        self.declared_spelling = False  # answers name a path as declared, not as asked
        self.station_conflicts = False  # 409 for a station that has a live session
        self.session_cap: float | None = None  # the longest session timeout granted (s)
        self.session_answer = "granted"  # the create answer names the timeout, or "absent"
        self.groups = Groups()  # `groups.timeout`: 120 s idle
        self.answer_with: tuple[int, bytes] | None = None  # every data answer: status, body
        self.calls: dict[str, int] = {}

    def build_app(self, app: web.Application) -> None:
        app.router.add_route("*", "/_pxc_api/{version}{tail:.*}", self._handle)
        app.router.add_get("/ehmi/{name}", self._ehmi)

    # -- the test-facing API ---------------------------------------------------------------

    def var(self, path: str) -> Leaf:
        """Return an elementary value by path (`Arp.Plc.Eclr/` may be left out)."""
        found = self.program.find(path if "/" in path else PREFIX + path)
        if found is None or not isinstance(found[1], Leaf):
            raise KeyError(path)
        return found[1]

    def get(self, path: str) -> Any:
        """Return a value as stored."""
        return self.var(path).value

    def set(self, path: str, value: Any) -> None:
        """Store a value without any check."""
        self.var(path).value = value

    def expire_groups(self) -> None:
        """Forget every group (120 s idle, or a restart of the web server)."""
        self.groups.clear()

    def download(self, renames: dict[str, str] | None = None) -> None:
        """Download the project again: a new projectCRC, renamed variables, groups dropped."""
        for old, new in (renames or {}).items():
            self.program.rename(old, new)
        self.crc = (self.crc * 1103515245 + 12345) % 2**32
        if not self.keep_groups:
            self.groups.clear()

    def animate(self, elapsed: float) -> None:
        """Let the temperature drift, the counter count and the demo's machines run."""
        run_machines(elapsed, self.get, self.set, MACHINES)
        self.set("MainInstance.Temperature", round(21.5 + 1.5 * math.sin(elapsed / 300), 1))
        self.set("MainInstance.Counter", (self.get("MainInstance.Counter") + 1) % 2**31)

    # -- HTTP ------------------------------------------------------------------------------

    async def _handle(self, request: web.Request) -> web.Response:
        """Check the version and the path's form, then run the command."""
        version, tail = request.match_info["version"], request.match_info["tail"]
        try:
            if version not in VERSIONS:
                raise Fault(404, "invalidApiVersion")
            if tail.endswith("/") and len(tail) > 1 and not self.trailing_slashes:
                raise Fault(404, "invalidPath")
            parts = [part for part in tail.split("/") if part]
            body = await request.read()
            if self.answer_with is not None and parts and parts[0] not in ("auth", "sessions"):
                status, raw = self.answer_with
                return web.Response(status=status, body=raw, content_type="application/json")
            return self._command(request, parts, body)
        except Fault as fault:
            return self._error(fault)

    def _command(self, request: web.Request, parts: list[str], body: bytes) -> web.Response:
        """Run one command of the interface."""
        method, head = request.method, parts[0] if parts else ""
        self.calls[f"{method} {head}"] = self.calls.get(f"{method} {head}", 0) + 1
        if not parts and method == "GET":
            return self._json({"version": "v1.8"}, status=200)
        if head == "auth" and method == "POST" and len(parts) == 2:
            return self._auth(parts[1], body_fields(body))
        if head == "sessions":
            return self._sessions(method, parts[1:], body_fields(body))
        user = self._user(request)
        if self.auth and not self.access.roles(user):
            raise Fault(403, self._reason("accessDenied", "noHmiLevel"))
        fields = {**query_fields(request), **body_fields(body)}
        self._keep_session(fields.get("sessionID"))
        if head == "groups" and not self.groups_served:
            raise Fault(405, "methodNotAllowed")
        if head == "variables" and method in ("GET", "POST") and len(parts) == 1:
            return self._read(fields)
        if head == "variables" and method == "PUT":
            return self._write(fields, user)
        if head == "groups":
            return self._groups(method, parts[1:], fields, body, query_fields(request))
        raise Fault(404, "invalidPath")

    def _json(self, data: dict[str, Any], status: int = 200, **headers: str) -> web.Response:
        """Return a JSON answer carrying the three fields every data answer carries."""
        data = {
            "apiVersion": API_VERSION,
            "projectCRC": self.crc,
            "userAuthenticationRequired": self.auth,
            **data,
        }
        return web.json_response(data, status=status, headers=headers)

    def _error(self, fault: Fault) -> web.Response:
        """Return an error answer: the documented shape, or another one in foreign mode."""
        headers = {"WWW-Authenticate": fault.challenge} if fault.challenge else {}
        if self.foreign:
            error: Any = {"code": secrets.randbelow(900) + 100, "message": f"E_{fault.reason}"}
        else:
            error = {"details": [{"reason": fault.reason}]}
        return web.json_response({"error": error}, status=fault.status, headers=headers)

    # -- variables and groups --------------------------------------------------------------

    def _spelled(self, full: str) -> str:
        """Return a full path as an answer names it: as asked, or as declared."""
        declared = self.program.declared(full) if self.declared_spelling else None
        return full if declared is None else declared[0] + declared[1]

    def _resolve(self, prefix: str, paths: list[str]) -> list[tuple[str, Variable, Any] | None]:
        """Return (full path, variable, node) of each path; None for an unknown one."""
        found: list[tuple[str, Variable, Any] | None] = []
        for path in paths:
            full = prefix + path.strip()
            hit = self.program.find(full)
            found.append(None if hit is None else (full, hit[0], hit[1]))
        return found

    def _read(self, fields: dict[str, Any]) -> web.Response:
        """GET or POST /variables: values in request order, paths in full."""
        prefix, paths = str(fields.get("pathPrefix") or ""), paths_of(fields.get("paths"))
        if not paths:
            raise Fault(400, "invalidPaths")
        entries: list[dict[str, Any]] = []
        for path, hit in zip(paths, self._resolve(prefix, paths), strict=True):
            if hit is None:
                if not self.unknown_entries:
                    raise Fault(404, self._reason("invalidNames", "unknownVariables"))
                reason = self._reason("invalidName", "noSuchVariable")
                entries.append({"path": prefix + path, "error": {"reason": reason}})
                continue
            entries.append(
                {"path": self._spelled(hit[0]), "value": as_json(hit[2], self.text_values)}
            )
        return self._json({"variables": entries})

    def _write(self, fields: dict[str, Any], user: str | None) -> web.Response:
        """PUT /variables: every variable checked, then stored; per-variable results."""
        if self.auth and "EHmiChanger" not in self.access.roles(user):
            raise Fault(403, self._reason("accessDenied", "notPermitted"))
        prefix, items = str(fields.get("pathPrefix") or ""), fields.get("variables")
        if not isinstance(items, list) or not items:
            raise Fault(400, "invalidVariables")
        paths = [str(item.get("path", "")) if isinstance(item, dict) else "" for item in items]
        hits = self._resolve(prefix, paths)
        if any(hit is None for hit in hits):
            raise Fault(404, self._reason("invalidNames", "unknownVariables"))
        entries: list[dict[str, Any]] = []
        for item, path, hit in zip(items, paths, hits, strict=True):
            assert hit is not None
            full, variable, node = hit
            entry: dict[str, Any] = {"path": path, "uri": f"/_pxc_api/api/variables/{full}"}
            entries.append(entry)
            if variable.read_only:
                if self.foreign:
                    raise Fault(403, "writeProtected")
                entry["error"] = {"details": [{"reason": "readOnly"}]}
                continue
            try:
                raw = item.get("value")
                if item.get("valueType") == "Variable":
                    source = self.program.find(prefix + str(raw))
                    raw = source[1].value if source and isinstance(source[1], Leaf) else None
                if not isinstance(node, Leaf):
                    raise Refused
                node.value = node.convert(raw)
                entry["value"] = node.json(self.text_values)
            except Refused:
                if self.foreign:
                    entry["value"] = None  # PyREST's reading: a null value is a failed write
                else:
                    entry["error"] = {"details": [{"reason": "invalidValue"}]}
        return self._json({"variables": entries})

    def _groups(
        self,
        method: str,
        parts: list[str],
        fields: dict[str, Any],
        body: bytes,
        query: dict[str, Any],
    ) -> web.Response:
        """Report, register, read and unregister groups (the Groups page)."""
        self.groups.expire()
        if method == "POST" and not parts:
            is_json = body.lstrip().startswith(b"{")
            if (self.bodies == "json" and not is_json) or (self.bodies == "form" and is_json):
                raise Fault(400, self._reason("invalidBody", "unsupportedFormat"))
            return self._register(fields)
        if method == "GET" and not parts:
            return self._json({"groups": self.groups.report(), "next": None})
        group = self.groups.use(parts[0]) if parts else None
        if group is None:
            raise Fault(404, self._reason("invalidGroupID", "groupUnknown"))
        if method == "DELETE":
            self.groups.delete(parts[0])
            return web.Response(status=204)
        entries: list[dict[str, Any]] = []
        for path, hit in zip(group.paths, self._resolve(group.prefix, group.paths), strict=True):
            if hit is None:
                entries.append({"path": path, "error": {"reason": "invalidName"}})
            else:
                named = self._spelled(hit[0])[len(group.prefix) :]
                entries.append({"path": named, "value": as_json(hit[2], self.text_values)})
        if str(query.get("summary", "0")) == "1":
            summary = [{"value": entry.get("value")} for entry in entries]
            return web.json_response({"apiVersion": API_VERSION, "variables": summary})
        prefix = group.prefix or None
        return self._json({"id": parts[0], "variablePathPrefix": prefix, "variables": entries})

    def _register(self, fields: dict[str, Any]) -> web.Response:
        """POST /groups: 404 when a name is unknown, 200 for an identical group, else 201."""
        prefix, paths = str(fields.get("pathPrefix") or ""), paths_of(fields.get("paths"))
        if not paths:
            raise Fault(400, "invalidPaths")
        hits = self._resolve(prefix, paths)
        if any(hit is None for hit in hits):
            raise Fault(404, self._reason("invalidNames", "unknownVariables"))
        status, group_id = self.groups.register(prefix, paths)
        variables = [
            {"path": path, "type": _type_of(hit)} for path, hit in zip(paths, hits, strict=True)
        ]
        answer = {"id": group_id, "variablePathPrefix": prefix or None, "variables": variables}
        location = f"{self.host}:{self.port}/_pxc_api/api/groups/{group_id}"
        return self._json(answer, status=status, Location=location)

    # -- dictionaries ----------------------------------------------------------------------

    async def _ehmi(self, request: web.Request) -> web.Response:
        """The variable and type dictionaries of the eHMI (the variable browser)."""
        try:
            user = self._user(request)
            if self.auth and not self.access.roles(user):
                raise Fault(403, self._reason("accessDenied", "noHmiLevel"))
        except Fault as fault:
            return self._error(fault)
        name = request.match_info["name"]
        if self.answer_with is not None:
            status, raw = self.answer_with
            return web.Response(status=status, body=raw, content_type="application/json")
        if name == "data.dictionary.json":
            return web.json_response(self.program.data_dictionary())
        if name == "type.dictionary.json":
            return web.json_response(self.program.type_dictionary())
        return web.json_response({"error": {"details": [{"reason": "notFound"}]}}, status=404)


def _type_of(hit: tuple[str, Variable, Any] | None) -> str:
    """Return the type a register answer names: the leaf's, else the variable's."""
    if hit is None:
        return ""
    return hit[1].type if hit[2] is hit[1].node else node_type(hit[2])
