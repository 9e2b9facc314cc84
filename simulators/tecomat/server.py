"""A Tecomat Foxtrot simulator: its web server's TecoApi (../shared/specs/tecomat-tecoapi-cs.txt).

GetInfo, GetList, GetObject, SetObject and PutObject with Basic or Digest authentication (stale
nonces renewed with 401.020), the 256-character URI limit, the variable limit (413.002/413.004),
the PutObject parser's limits (3.6) and every error of 3.7 a client can provoke.
"""

from __future__ import annotations

from collections import Counter, deque
from collections.abc import Callable
from datetime import UTC, datetime
import json
import math
from typing import Any
from urllib.parse import unquote

from aiohttp import web

from ..base import HttpSimulator
from ..machines import run_machines
from .answers import read
from .auth import Authenticator
from .program import (
    CLOCK,
    MACHINES,
    Node,
    Pairs,
    assignments,
    default_program,
    parse,
    parse_body,
    resolve,
    write,
)
from .values import Fault, Var, declaration, dumps, worded

DEFAULT_USER = "admin"
DEFAULT_PASSWORD = "Foxtrot-1"
MAX_URI = 256
HISTORY = 1000
SERVER = "TecoApi/1.0.0 (Fx2 CP2080I v1.1 PP 0004)"
PUBLIC_FILE_ERRORS = {
    "missing": ("500.010", "Public file '{}' is not found"),
    "too_big": ("500.011", "Public file '{}' is too big"),
    "unreadable": ("500.012", "Reading of public file '{}' failed"),
}


class TecomatSimulator(HttpSimulator):
    """A Foxtrot CPU running the spec's example program, with its TecoApi.

    Knobs for tests: `mode` (RUN/HALT/ERR), `variables` (the program), `instances` (top-level
    entries that are program instances, listed with their variables), `clock` (naive PLC
    time; writing `setTime` sets it, as a PLC program would), `public_file` ("ok", "missing",
    "too_big", "unreadable"), `rewrite` (edit each JSON answer), `leaf_names` (400.005 and
    400.015 name only the item where the PLC stopped, `sport` for myObject.favorites.sport),
    `array_answers`, `asked_case`, `element_spelling`, `real_format`, `rename_stamps`,
    `error_texts`, `whole_arrays`, `list_types` (see READINGS.md),
    `stale_nonce()`, `rename()`; the demo calls `animate()`.
    `bodies` keeps the last PutObject bodies and `uris` the last request targets; `calls`
    counts services; `auth.accepted` counts the credentials accepted, by method and qop.
    """

    common_name = "tecomat-foxtrot"

    def __init__(
        self,
        *,
        auth: str = "digest",
        users: dict[str, str] | None = None,
        tls: bool = False,
        max_variables: int = 128,
        bench: int = 10_000,
    ) -> None:
        super().__init__()
        self.tls = tls
        self.auth = Authenticator(
            auth, {DEFAULT_USER: DEFAULT_PASSWORD} if users is None else users
        )
        self.max_variables = max_variables  # Foxtrot CP-1xxx: 128, CP-2xxx: 256
        self.max_name = 128 if max_variables <= 128 else 256  # 400.007 follows the same CPU line
        self.mode = "RUN"
        self.clock = CLOCK
        self.public_file = "ok"
        self.variables: dict[str, Node] = default_program(bench)
        self.instances = {"Main"}
        self.bodies: deque[bytes] = deque(maxlen=HISTORY)  # bounded: the demo runs for days
        self.uris: deque[str] = deque(maxlen=HISTORY)
        self.calls: Counter[str] = Counter()
        self.rewrite: Callable[[bytes], bytes] | None = None
        self.leaf_names = False
        self.array_answers = "keyed"  # how elements of an array come (answers.ARRAY_ANSWERS)
        self.drop_writes = False  # PutObject answered 204 without storing anything
        self.asked_case = False  # answers spell names as asked, not as declared
        self.element_spelling = "any"  # arr2[1][3] and/or arr2[1,3] (answers.ELEMENT_SPELLINGS)
        self.real_format = "fixed"  # how REALs are printed (values.REAL_FORMATS)
        self.stamp = "E28AE29B"  # GetInfo's userProg.stamp
        self.rename_stamps = True  # rename() builds a new program: a new stamp
        self.error_texts = "manual"  # how 400.005 and 400.015 are worded (ERROR_TEXTS)
        self.whole_arrays = "list"  # how an array read whole comes (values.WHOLE_ARRAYS)
        self.list_types = False  # GetList gives each variable's declared type (READINGS.md 18)

    def build_app(self, app: web.Application) -> None:
        app.router.add_route("*", "/TecoApi{tail:.*}", self._handle)

    # -- the test-facing API ---------------------------------------------------------------

    def stale_nonce(self, times: int = 1) -> None:
        """Renew the digest nonce: the next `times` requests get 401.020 "New balls", stale=true."""
        self.auth.stale_nonce(times)

    def animate(self, elapsed: float) -> None:
        """Let the outside and inside temperatures of 5.3 drift: slow waves, in 0.1 steps.

        The demo's machines (`program.MACHINES`) run too: simulators/machines.py.
        """
        run_machines(elapsed, self.get, self.set, MACHINES)
        outside = -0.5 + 4.0 * math.sin(2 * math.pi * elapsed / 1800)
        inside = 22.1 + 0.6 * math.sin(2 * math.pi * elapsed / 1200)
        for path, value in (("Main.myObject1.value", outside), ("Main.myObject2.value", inside)):
            variable = self.var(path)
            variable.value = variable.convert(round(value, 1))

    def rename(self, old: str, new: str) -> None:
        """Rename a variable or member (a new program version): `old` is a path, `new` a name."""
        parts = parse(old)
        if not parts or not isinstance(parts[-1], str):
            raise ValueError(f"{old!r} does not name a variable")
        _canonical, parent = resolve(self.variables, parts[:-1])
        if not isinstance(parent, dict):
            raise TypeError(f"{old!r} is not a member of a structure")
        key = next(name for name in parent if name.lower() == parts[-1].lower())
        parent[new] = parent.pop(key)
        if self.rename_stamps:
            self.stamp = f"{(int(self.stamp, 16) * 31 + 7) & 0xFFFFFFFF:08X}"

    def var(self, path: str) -> Var:
        """Return an elementary variable by path (case-insensitive)."""
        _canonical, node = resolve(self.variables, parse(path) or [])
        if not isinstance(node, Var):
            raise TypeError(f"{path} is not an elementary variable")
        return node

    def get(self, path: str) -> Any:
        """Return a variable's value as stored (TIME/TOD in ms, DATE a date, DT naive)."""
        return self.var(path).value

    def set(self, path: str, value: Any) -> None:
        """Store a value without any check."""
        self.var(path).value = value

    # -- HTTP ------------------------------------------------------------------------------

    async def _handle(self, request: web.Request) -> web.StreamResponse:
        """Authenticate, then run the service the path names."""
        body = await request.read()
        self.uris.append(request.raw_path)
        try:
            fault = self.auth.check(request, body)
            if fault is not None:
                raise fault
            if len(request.raw_path) > MAX_URI:  # the spec gives the limit but no error code
                raise Fault("414.000", "Request-URI Too Long")
            return self._service(request, body)
        except Fault as fault:
            return self._error(fault)

    def _service(self, request: web.Request, body: bytes) -> web.Response:
        """Run one service."""
        service = request.match_info["tail"].strip("/")
        if not service:
            raise Fault("400.014", "Service is not specified")
        handlers = {
            ("GET", "getinfo"): self._get_info,
            ("GET", "getlist"): self._get_list,
            ("GET", "getobject"): self._get_object,
            ("GET", "setobject"): self._set_object,
            ("PUT", "putobject"): self._put_object,
        }
        handler = handlers.get((request.method, service.lower()))
        if handler is None:
            raise Fault("501.013", f"Unimplemented service 'HTTP {request.method} | {service}'")
        self.calls[service] += 1
        if service.lower() != "getinfo" and self.public_file in PUBLIC_FILE_ERRORS:
            code, message = PUBLIC_FILE_ERRORS[self.public_file]
            raise Fault(code, message.format("DOC_TECOAPI.pub"))
        if service.lower() != "getinfo" and not self.variables:
            raise Fault("400.006", "No variable is found")
        return handler(request.query_string, body)

    def _headers(self) -> dict[str, str]:
        """Return the headers every answer carries."""
        return {"Server": SERVER, "Cache-Control": "no-cache"}

    def _json(self, data: Any) -> web.Response:
        """Return a 200 answer with a JSON body (edited by `rewrite` when set)."""
        body = dumps(data, self.real_format).encode()
        if self.rewrite is not None:
            body = self.rewrite(body)
        return web.Response(body=body, content_type="application/json", headers=self._headers())

    def _error(self, fault: Fault) -> web.Response:
        """Return an error answer (3.7); a 401 carries a new challenge."""
        headers = self._headers()
        if fault.status == 401:
            headers["WWW-Authenticate"] = self.auth.challenge(stale=fault.code == "401.020")
        stamp = datetime.now(UTC).strftime("%Y-%m-%dT%H:%M:%S.%f")[:-3] + "Z"
        message = worded(fault, self.error_texts)
        error = {"error": {"code": fault.code, "message": message, "time": stamp}}
        return web.Response(
            status=fault.status,
            body=json.dumps(error).encode(),
            content_type="application/json",
            headers=headers,
        )

    # -- services --------------------------------------------------------------------------

    def _get_info(self, query: str, body: bytes) -> web.Response:
        stamp = f"{self.clock:%Y-%m-%dT%H:%M:%S}.{self.clock.microsecond // 1000:03d}Z"
        plc = {
            "family": "Fx2",
            "type": "CP2080",
            "serialNumber": "PP 0004",
            "version": "Fx2 CP2080I v1.1",
            "mac": "F8-DC-7A-11-F4-DC",
            "mode": self.mode.ljust(4),  # the spec shows "RUN " and "HALT"
            "userProg": {
                "name": "DOC_TECOAPI v1.0",
                "compiled": "2018-01-18T16:39:38.000Z",
                "stamp": self.stamp,
            },
            "time": stamp,
        }
        return self._json({"api": {"version": "TecoApi v1.0.0"}, "plc": plc})

    def _get_list(self, query: str, body: bytes) -> web.Response:
        form = "struct"
        for param in filter(None, query.split("&")):
            name, equals, value = param.partition("=")
            if not name:
                raise Fault("400.017", "Name of parameter is empty")
            if name != "listType":
                raise Fault("400.018", f"Unknown parameter (service: 'GetList', param: '{name}')")
            if not equals or not value:
                raise Fault(
                    "400.019", f"Value of parameter is empty (service: 'GetList', param: '{name}')"
                )
            if value not in ("struct", "array"):
                raise Fault(
                    "400.016", f"Unknown value of parameter (param: '{name}', value: '{value}')"
                )
            form = value
        listing: dict[str, Any] = {}
        for name, node in self.variables.items():
            members = node if name in self.instances and isinstance(node, dict) else {}
            listing[name] = {member: self._listed(value) for member, value in members.items()}
            if not members:
                listing[name] = self._listed(node)
        if form == "array":
            return self._json([{name: value} for name, value in listing.items()])
        return self._json(listing)

    def _listed(self, node: Node) -> dict[str, str]:
        """Return a variable's GetList entry: {} (3.3), or its declared type (`list_types`)."""
        kind = declaration(node) if self.list_types else None
        return {"type": kind} if kind else {}

    def _names(self, query: str) -> list[str]:
        """Return the variable names of a GetObject or SetObject query."""
        if not query:
            raise Fault("400.001", "Bad parameters (any PLC variable is not specified)")
        names = [unquote(name) for name in query.split("&")]
        if len(names) > self.max_variables:
            raise Fault(
                "413.002",
                f"Too many variables in one request (requested: {len(names)}, "
                f"allowed: {self.max_variables})",
            )
        for name in names:
            if not name:
                raise Fault("400.003", "Name of variable is empty")
            if len(name.partition("=")[0]) > self.max_name:
                raise Fault("400.007", f"Name of variable '{name[:20]}...' is too long")
        return names

    def _get_object(self, query: str, body: bytes) -> web.Response:
        names = self._names(query)
        return self._json(
            read(
                self.variables,
                names,
                self.max_variables,
                leaf_names=self.leaf_names,
                array_answers=self.array_answers,
                asked_case=self.asked_case,
                element_spelling=self.element_spelling,
                whole_arrays=self.whole_arrays,
            )
        )

    def _set_object(self, query: str, body: bytes) -> web.Response:
        pairs = Pairs()
        for item in self._names(query):
            name, equals, text = item.partition("=")
            if not name:
                raise Fault("400.017", "Name of parameter is empty")
            if not equals or not text:
                raise Fault(
                    "400.019",
                    f"Value of parameter is empty (service: 'SetObject', param: '{name}')",
                )
            try:  # true, 1005, "testing is funny" (3.5), or bare text: arr1[5]=five (5.2)
                value = json.loads(text)
            except ValueError:
                value = text
            pairs.append((name, value))
        self._apply(pairs)
        return web.Response(headers=self._headers())

    def _put_object(self, query: str, body: bytes) -> web.Response:
        self.bodies.append(body)
        pairs = parse_body(body)
        if not self.drop_writes:  # firmware that answers 204 to values it did not take
            self._apply(pairs)
        return web.Response(status=204, headers=self._headers())

    def _apply(self, pairs: Pairs) -> None:
        """Check every assignment, then store them all (nothing is written on an error)."""
        found = assignments(pairs, [])
        for variable, value in write(
            self.variables, found, self.max_variables, leaf_names=self.leaf_names
        ):
            variable.value = value
            if variable is self.variables.get("setTime"):
                self.clock = value
