"""A SoftPLC runtime with WEB.TLM (../shared/specs/softplc-web-tlm-rest.txt).

GET /dt (file listing), GET /dt/all, GET /dt/<file>:<element>[?count=], POST /dt and PUT /dt
with XML bodies, tags of a descriptor table, `normalize_response_addr`, and PUT authentication
by SSL client certificate (`enable_put_auth`). What the manual leaves open has switches, and its
answers are the simulator's own inventions, not the client's guesses:

- `bad_item`: "request" fails the whole request for one bad item; "item" fails that item only
  (`item_error` "attribute" or "child" says how);
- `error_status` and `error_style` ("xml", "html", "text"): the failed request's answer;
- `past_end`: "truncate" answers a count past the end of a file with what exists; "error"
  treats it as a bad item;
- `foreign_codes`: errors carry invented codes and another shape (status 500, HTML, child);
- `cert_check`: "request" accepts any certificate in the handshake and refuses a PUT with 403;
  "handshake" refuses an untrusted certificate in the TLS handshake;
- `tag_case`: "blind" finds a tag in any case, "exact" only as the table spells it;
- `tag_reply`: a tag's item is answered with the tag as the "table" spells it, as "sent", or
  with the "address" it stands for (normalised when `normalize` is on);
- `short`: "element" reads I1 (no colon) as I:1, "file" as file I1, element 0;
- `fixed`: normalised O, I and S files are "short" (O:0000, the manual) or "numbered"
  (O0000:0000);
- `reply_forms`: a request's "I:3" (a reply's form: no file number) is "taken" or "refused";
- `words`: integer words printed as the "manual" shows (O and I in hex, others unsigned
  decimal), all in "hex", or "signed" decimal;
- `extra`: every `<data>` of an answer carries attributes no manual names, one namespaced;
- `order`: answer items in the "request" order or "reversed";
- `reals`: floats (stored as IEEE singles) printed as C's "%.7g" ("g7"), with a decimal
  "comma" (a localised firmware), in "exponent" form, with nine digits ("long"), four
  ("short"), or "grouped" ("1.234,5": digits grouped, decimal comma);
- `busy`: HTTP statuses (503...) answered to the next requests, whatever they ask, after
  `busy_after` more requests answered as usual; `busy_retry` says whether they carry a
  Retry-After of `busy_wait` seconds: "none", "seconds", or "date" (an HTTP-date);
  `busy_acts`: a PUT answered busy was written all the same (a firmware that breaks HTTP).

simulators/softplc/READINGS.md lists what each switch answers and where each reading comes from.

The demo (`python -m simulators --demo --certs DIR`) runs it as `DEMO_OPTIONS` say: HTTPS with
PUT authentication on, and a client certificate the PLC trusts written into DIR at every start
(`keep_client_certificate`); scripts/develop prints the paths to give in the connection form.
"""

from __future__ import annotations

from collections import deque
from datetime import UTC, datetime, timedelta
from email.utils import format_datetime
import math
from pathlib import Path
import ssl
import struct
from typing import Any, ClassVar
from urllib.parse import unquote
from xml.etree import ElementTree as ET  # the simulator parses the client's own requests

from aiohttp import web
from cryptography.hazmat.primitives import serialization

from ..base import HttpSimulator
from .certificates import issue, pem
from .datatable import Bad, File, Target, default_files, normalised, resolve

HISTORY = 200
DEFAULT_TAGS = {"timer1": "T4:0", "important_int": "N7:10", "setpoint": "F8:1"}


def printed_real(value: float, style: str) -> str:
    """Return a float as the PLC prints it under the `reals` switch."""
    if style == "exponent":
        return f"{value:e}"
    if style in ("long", "short"):
        return f"{value:.{9 if style == 'long' else 4}g}"
    if style == "grouped":
        return f"{value:,.6f}".replace(",", "_").replace(".", ",").replace("_", ".")
    text = f"{value:.7g}"
    return text.replace(".", ",") if style == "comma" else text


class SoftplcSimulator(HttpSimulator):
    """A SoftPLC with WEB.TLM; knobs are attributes (see the module's docstring)."""

    common_name = "softplc"
    DEMO_OPTIONS: ClassVar[dict[str, Any]] = {"tls": True, "put_auth": True, "bench": 0}

    def __init__(
        self,
        *,
        tls: bool = False,
        put_auth: bool = False,
        normalize: bool = False,
        bench: int = 1000,
    ) -> None:
        super().__init__()
        self.tls = tls
        self.put_auth = put_auth
        self.normalize = normalize
        self.files: dict[tuple[str, int], File] = default_files(bench)
        self.tags = dict(DEFAULT_TAGS)
        self.bad_item = "request"
        self.item_error = "attribute"
        self.error_status = 400
        self.error_style = "xml"
        self.past_end = "truncate"
        self.foreign_codes = False
        self.cert_check = "request"
        self.tag_case = "blind"
        self.tag_reply = "table"
        self.short = "element"
        self.fixed = "short"
        self.extra = False
        self.reply_forms = "taken"
        self.words = "manual"
        self.order = "request"
        self.reals = "g7"  # how floats are printed (see the module's docstring)
        self.busy: deque[int] = deque()
        self.busy_after = 0  # requests served as usual before the `busy` statuses start
        self.busy_retry = "none"  # Retry-After of a busy answer: "none", "seconds", "date"
        self.busy_wait = 1  # the seconds that Retry-After asks
        self.busy_acts = False  # a PUT answered busy is written all the same
        self.bodies: deque[bytes] = deque(maxlen=HISTORY)
        self.items: deque[int] = deque(maxlen=HISTORY)  # <data> items of each POST
        self.rewrite: Any = None  # bytes -> bytes applied to every 2xx answer (hostile replies)
        self._client_ca = issue("softplc-clients", None)
        self._stranger_ca = issue("someone-else", None)
        self.form_fields: dict[str, str] = {}  # what the demo prints for the connection form

    # -- certificates -------------------------------------------------------------------

    def client_certificate(self, *, trusted: bool = True) -> tuple[str, str]:
        """Return (PEM certificate, PEM key) of a client certificate the PLC trusts (or not)."""
        issuer = self._client_ca if trusted else self._stranger_ca
        return pem(*issue("home-assistant", issuer))

    def keep_client_certificate(self, folder: Path) -> None:
        """Write a client certificate this PLC trusts, and its key, into folder (the demo's).

        Issued anew at every start (the PLC's client CA lives as long as the process); the
        paths stay the same, so an entry that stored them keeps writing after a restart.
        """
        certificate, key = self.client_certificate()
        folder.mkdir(parents=True, exist_ok=True)
        files = {"Client certificate": folder / "softplc-client.pem"}
        files["Client key"] = folder / "softplc-client.key"
        files["Client key"].touch(mode=0o600)
        files["Client key"].write_text(key)
        files["Client certificate"].write_text(certificate)
        self.form_fields = {label: str(path.resolve()) for label, path in files.items()}

    def use_certificate(self, chain: bytes, key: bytes) -> None:
        """Serve the certificate, and ask clients for theirs (optional: reads need none)."""
        super().use_certificate(chain, key)
        assert self._ssl is not None
        authorities = [self._client_ca[0]]
        if self.cert_check == "request":
            authorities.append(self._stranger_ca[0])  # any certificate passes the handshake
        for authority in authorities:
            self._ssl.load_verify_locations(
                cadata=authority.public_bytes(serialization.Encoding.PEM).decode()
            )
        self._ssl.verify_mode = ssl.CERT_OPTIONAL

    def animate(self, elapsed: float) -> None:
        """Let F8:0 (a temperature) drift and the timer T4:0 count.

        The demo boiler's water (N7:50, tenths of a degree) drifts too and raises Overheat (bit
        0 of N7:70) above its set point (N7:52).
        """
        self.files["F", 8].words[0] = round(21.5 + 1.5 * math.sin(2 * math.pi * elapsed / 900), 1)
        self.files["T", 4].words[2] = int(elapsed * 10) % 4000
        words = self.files["N", 7].words
        words[50] = water = round(550 + 50 * math.sin(2 * math.pi * elapsed / 600))
        words[70] = int(words[70]) & ~1 | int(0 < int(words[52]) < water)

    # -- HTTP -------------------------------------------------------------------------

    def build_app(self, app: web.Application) -> None:
        app.middlewares.append(self._busy)
        app.router.add_get("/dt", self._listing)
        app.router.add_get("/dt/all", self._all)
        app.router.add_get("/dt/{ad}", self._get)
        app.router.add_post("/dt", self._post)
        app.router.add_put("/dt", self._put)

    async def _listing(self, request: web.Request) -> web.Response:
        links = "".join(
            f'<li><a href="/dt/{f.type if f.type in "OIS" else f"{f.type}{f.number}"}:0">'
            f"{f.type}{f.number}</a> ({f.elements} elements)</li>"
            for f in self.files.values()
        )
        return web.Response(
            text=f"<html><body><ul>{links}</ul></body></html>", content_type="text/html"
        )

    async def _all(self, request: web.Request) -> web.Response:
        items = [(f"{f.type}{f.number}:0", None) for f in self.files.values() if f.type != "PD"]
        return self._answer(self._read_items(items))

    async def _get(self, request: web.Request) -> web.Response:
        count = request.query.get("count")
        return self._answer(self._read_items([(unquote(request.match_info["ad"]), count)]))

    @web.middleware
    async def _busy(self, request: web.Request, handler: web.Handler) -> web.StreamResponse:
        """Answer a queued BUSY status instead of the request (an overloaded PLC)."""
        if self.busy and self.busy_after:
            self.busy_after -= 1
        elif self.busy:
            status = self.busy.popleft()
            if self.busy_acts and request.method == "PUT":
                await handler(request)
            else:
                self.bodies.append(await request.read())
            headers = {}
            if self.busy_retry == "seconds":
                headers["Retry-After"] = str(self.busy_wait)
            elif self.busy_retry == "date":
                when = datetime.now(UTC) + timedelta(seconds=self.busy_wait)
                headers["Retry-After"] = format_datetime(when, usegmt=True)
            return web.Response(status=status, text="Service Unavailable", headers=headers)
        response: web.StreamResponse = await handler(request)
        return response

    async def _post(self, request: web.Request) -> web.Response:
        body = await request.read()
        self.bodies.append(body)
        try:
            items = [(d.get("ad", ""), d.get("count")) for d in self._data(body)]
        except Bad as err:
            return self._failure(str(err), 400)
        self.items.append(len(items))
        return self._answer(self._read_items(items))

    async def _put(self, request: web.Request) -> web.Response:
        body = await request.read()
        self.bodies.append(body)
        if self.put_auth and not self._trusted(request):
            return self._failure("client certificate required for PUT", 403)
        try:
            data = self._data(body)
        except Bad as err:
            return self._failure(str(err), 400)
        written: list[ET.Element | Bad] = []
        for element in data:
            try:
                written.append(self._write(element))
            except Bad as err:
                if self.bad_item == "request":
                    return self._failure(str(err), self.error_status)
                written.append(Bad(str(err), element.get("ad", "")))
        return self._answer(self._document(written))

    # -- what the handlers share -----------------------------------------------------

    def _trusted(self, request: web.Request) -> bool:
        """True when the request came with a client certificate issued by the PLC's CA."""
        if request.transport is None:
            return False
        peer = request.transport.get_extra_info("peercert")
        if not peer:
            return False
        issuer = {key: value for part in peer.get("issuer", ()) for key, value in part}
        return issuer.get("commonName") == "softplc-clients"

    def _data(self, body: bytes) -> list[ET.Element]:
        try:
            root = ET.fromstring(body)
        except ET.ParseError as err:
            raise Bad(f"malformed XML: {err}") from None
        if root.tag != "files":
            raise Bad("the body is not a <files> element")
        return [child for child in root if child.tag == "data"]

    def _read_items(self, items: list[tuple[str, str | None]]) -> web.Response | ET.Element:
        answers: list[ET.Element | Bad] = []
        for ad, count in items:
            try:
                answers.append(self._read(ad, count))
            except Bad as err:
                if self.bad_item == "request":
                    return self._failure(str(err), self.error_status)
                answers.append(Bad(str(err), ad))
        return self._document(answers)

    def _target(self, ad: str) -> tuple[Target, str]:
        """Return the target of an ad or tag, and the ad the answer carries."""
        asked = ad.strip()
        if self.tag_case == "exact":
            tag = asked if asked in self.tags else None
        else:
            tag = next((name for name in self.tags if name.lower() == asked.lower()), None)
        if not tag and self.reply_forms == "refused" and asked[:2].upper() in ("O:", "I:", "S:"):
            raise Bad(f"invalid datatable address '{ad}'")
        target = resolve(self.files, self.tags[tag] if tag else ad, self.short)
        shown = normalised(target, self.fixed) if self.normalize else ad
        if tag and self.tag_reply == "address":
            return target, shown if self.normalize else self.tags[tag]
        if tag:  # "addresses will be switched out with tags"
            return target, asked if self.tag_reply == "sent" else tag
        return target, shown

    def _read(self, ad: str, count_text: str | None) -> ET.Element:
        target, shown = self._target(ad)
        file = target.file
        if target.pid or target.word is not None:
            value = (
                file.pids[target.element][target.pid]
                if target.pid
                else file.words[
                    target.element * file.width + target.word  # type: ignore[operator]
                ]
            )
            return self._element(shown, None, [value], file)
        try:
            count = -1 if count_text is None else int(count_text)
        except ValueError:
            raise Bad(f"invalid count '{count_text}'") from None
        room = file.elements - target.element
        if count < 0 or count > room:
            if count > room and self.past_end == "error":
                raise Bad(f"count {count} runs past the end of {file.type}{file.number}")
            count = room
        start = target.element * file.width
        return self._element(shown, count, file.words[start : start + count * file.width], file)

    def _write(self, data: ET.Element) -> ET.Element:
        ad = data.get("ad", "")
        target, _shown = self._target(ad)
        file = target.file
        values = (data.text or "").split()
        if target.pid or target.word is not None:
            if len(values) != 1:
                raise Bad(f"a word write takes one value, not {len(values)}")
            if target.pid:
                file.pids[target.element][target.pid] = self._number(values[0], file)
            else:
                file.words[target.element * file.width + target.word] = self._number(
                    values[0], file
                )
            return self._read(ad, None)
        count = data.get("count")
        if count is None or not count.lstrip("-").isdigit() or int(count) != len(values):
            raise Bad(f"count {count} does not match the {len(values)} values")
        if file.width != 1 or target.element + len(values) > file.elements:
            raise Bad(f"cannot write {len(values)} elements at {ad}")
        for offset, text in enumerate(values):
            file.words[target.element + offset] = self._number(text, file)
        return self._read(ad, count)

    def _number(self, text: str, file: File) -> int | float:
        try:
            if file.type in ("F", "PD"):
                number = float(int(text, 16)) if text.lower().startswith("0x") else float(text)
                return float(struct.unpack("<f", struct.pack("<f", number))[0])
            value = int(text, 0) if text.lower().startswith("0x") else int(text)
        except ValueError:
            raise Bad(f"invalid value '{text}'") from None
        if not -0x8000 <= value <= 0xFFFF:
            raise Bad(f"value {text} does not fit a word")
        return value & 0xFFFF

    def _element(self, ad: str, count: int | None, values: list[Any], file: File) -> ET.Element:
        element = ET.Element("data", ad=ad)
        if count is not None:
            element.set("count", str(count))
        if file.type in ("F", "PD"):
            texts = [printed_real(float(v), self.reals) for v in values]
        elif self.words == "hex" or (self.words == "manual" and file.type in ("O", "I")):
            texts = [f"0x{int(v):04x}" for v in values]
        elif self.words == "signed":
            texts = [str(int(v) - 0x10000 if int(v) & 0x8000 else int(v)) for v in values]
        else:
            texts = [str(int(v)) for v in values]
        element.text = "\n" + " ".join(texts) + "\n"
        return element

    def _document(self, answers: list[ET.Element | Bad]) -> ET.Element:
        root = ET.Element("files")
        if self.extra:
            root.set("xmlns:w", "urn:softplc:web")
        for answer in reversed(answers) if self.order == "reversed" else answers:
            element = self._bad_element(answer) if isinstance(answer, Bad) else answer
            if self.extra:
                element.set("w:scan", "1734")
                element.set("quality", "good")
            root.append(element)
        return root

    def _bad_element(self, bad: Bad) -> ET.Element:
        text, ad = str(bad.args[0]), str(bad.args[1]) if len(bad.args) > 1 else ""
        element = ET.Element("data", ad=ad)
        if self.foreign_codes or self.item_error == "child":
            error = ET.SubElement(element, "fault" if self.foreign_codes else "error")
            error.text = f"WT-{len(text) * 37 % 900 + 100}: {text}" if self.foreign_codes else text
        else:
            element.set("error", text)
        return element

    def _answer(self, document: web.Response | ET.Element) -> web.Response:
        if isinstance(document, web.Response):
            return document
        body = b'<?xml version="1.0" encoding="utf-8" ?>\n' + ET.tostring(document)
        if self.rewrite is not None:
            body = self.rewrite(body)
        return web.Response(body=body, content_type="text/xml", charset="utf-8")

    def _failure(self, text: str, status: int) -> web.Response:
        if self.foreign_codes:
            status = 500 if status not in (401, 403) else status
            text = f"WT-E{status * 7 % 97:02d} {text}"
        style = "html" if self.foreign_codes else self.error_style
        if style == "html":
            body = f"<html><body><h1>Error</h1><p>{text}</p></body></html>"
            return web.Response(status=status, text=body, content_type="text/html")
        if style == "text":
            return web.Response(status=status, text=text)
        body = f'<?xml version="1.0"?><files><error code="{status}">{text}</error></files>'
        return web.Response(status=status, text=body, content_type="text/xml")
