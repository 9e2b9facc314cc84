"""The client certificate WEB.TLM may ask of a PUT ("client_auth = ssl"), in an SSL context.

The certificate and key come as pasted PEM or as absolute file paths (options
`client_certificate` and `client_key`); an encrypted key is not supported. Nothing here logs or
quotes either of them (nor what was given as a path: it may be PEM without its first line).
A file is read by this module, at most MAX_PEM bytes, never by OpenSSL from its path.
"""

from __future__ import annotations

import asyncio
from collections.abc import Mapping
import contextlib
import hashlib
import os
from pathlib import Path
import ssl
import tempfile

from ...errors import (
    PlcAuthenticationError,
    PlcError,
    PlcOptionError,
    PlcTlsError,
)
from ...http import fetch_certificate
from ...types import ConnectionConfig, TlsMode

CERTIFICATE = "client_certificate"
KEY = "client_key"
_REFUSALS = (
    "UNKNOWN_CA",
    "BAD_CERTIFICATE",
    "CERTIFICATE_UNKNOWN",
    "CERTIFICATE_REQUIRED",
    "CERTIFICATE_EXPIRED",
    "CERTIFICATE_REVOKED",
    "UNSUPPORTED_CERTIFICATE",
    "ACCESS_DENIED",
    "DECRYPT_ERROR",
)
"""TLS alerts a server sends about the client's certificate (RFC 8446 6.2)."""
_WHAT = {CERTIFICATE: ("client certificate", "CERTIFICATE"), KEY: ("client key", "PRIVATE KEY")}
MAX_PEM = 256 * 1024
"""Bytes a certificate or key file may have: a chain of ten certificates is about 20 KB."""


class MaterialError(PlcOptionError):
    """A client certificate or key that cannot be used, found before anything is sent."""


def check_material(value: object, option: str) -> str:
    """Return pasted PEM or an absolute path, stripped; raise MaterialError (never quoting it)."""
    what, marker = _WHAT[option]
    if not isinstance(value, str):
        raise MaterialError(f"the {what} is PEM text or a file path", option)
    text = value.strip()
    if text.startswith("-----BEGIN"):
        if marker not in text or "-----END" not in text:
            raise MaterialError(f"the {what} is not a PEM {marker.lower()}", option)
        return text + "\n"
    if "\x00" in text:
        raise MaterialError(f"the {what} holds a NUL character", option)
    if not text or "\n" in text or not os.path.isabs(text):
        raise MaterialError(f"the {what} is pasted PEM text or an absolute file path", option)
    return text


def read_pem(path: str, option: str) -> str:
    """Return a PEM file's text, read up to MAX_PEM bytes; raise MaterialError on the option."""
    what = _WHAT[option][0]
    if not Path(path).is_file():  # also a NUL in the path; a FIFO would block the read
        raise MaterialError(f"the {what} file is missing or not a regular file", option)
    try:
        with Path(path).open("rb") as file:
            data = file.read(MAX_PEM + 1)
    except (OSError, ValueError):
        raise MaterialError(f"the {what} file cannot be read", option) from None
    if len(data) > MAX_PEM:
        raise MaterialError(f"the {what} file is larger than {MAX_PEM // 1024} KiB", option)
    return data.decode("ascii", "replace")


def resolve_material(
    folder: str, submitted: Mapping[str, object], stored: Mapping[str, object]
) -> dict[str, str]:
    """Return the submitted certificate and key, paths made absolute in `folder` (blocking).

    Each is checked by loading it with its partner (the stored one when only one is given):
    a path outside the folder, a file that is missing, a certificate that does not parse, or a
    key that is not the certificate's raise MaterialError on the option at fault.
    """
    root = Path(folder).resolve()
    resolved: dict[str, str] = {}
    for option, (what, _marker) in _WHAT.items():
        value = str(submitted.get(option) or "").strip()
        if not value or value.startswith("-----BEGIN"):
            if value:
                resolved[option] = value
            continue
        if "\x00" in value:
            raise MaterialError(f"the {what} holds a NUL character", option)
        try:
            path = Path(root, value).resolve()
        except (OSError, ValueError):
            raise MaterialError(f"the {what} file cannot be found", option) from None
        if not path.is_relative_to(root):
            raise MaterialError(
                f"the {what} file is outside the configuration folder", option, outside=True
            )
        if not path.is_file():
            raise MaterialError(f"the {what} file is not in the configuration folder", option)
        resolved[option] = str(path)
    if resolved:
        pair = pem_options({**stored, **resolved})
        try:
            check_pair(pair[CERTIFICATE], pair[KEY])
        except MaterialError as err:
            if err.option in resolved:
                raise
            (given,) = resolved  # the stored partner loaded before: the new one does not fit it
            mismatch = f"the {_WHAT[given][0]} does not fit the stored {_WHAT[err.option][0]}"
            raise MaterialError(mismatch, given) from None
    return resolved


def check_pair(certificate: str, key: str) -> None:
    """Load a certificate and its key as a connection would (blocking); blame the one at fault."""
    context = ssl.SSLContext(ssl.PROTOCOL_TLS_CLIENT)
    text = certificate
    if not certificate.startswith("-----BEGIN"):
        text = read_pem(certificate, CERTIFICATE)
    if not key.startswith("-----BEGIN"):
        read_pem(key, KEY)
    try:
        context.load_verify_locations(cadata=text)
    except (ssl.SSLError, OSError, ValueError):
        raise MaterialError(
            "the client certificate is not a readable PEM certificate", CERTIFICATE
        ) from None
    try:
        _load(context, certificate, key)
    except PlcAuthenticationError:
        raise MaterialError(
            "the client key is not the unencrypted PEM private key of that certificate", KEY
        ) from None


def has_certificate(config: ConnectionConfig) -> bool:
    """True when the settings carry a client certificate and its key."""
    return bool(config.options.get(CERTIFICATE)) and bool(config.options.get(KEY))


async def client_context(config: ConnectionConfig) -> ssl.SSLContext:
    """Return an SSL context presenting the client certificate, checking the PLC per TLS mode.

    PIN: the PLC's certificate is fetched, compared with the pin, then trusted as the only
    anchor (partial chain), so the connection that carries the request is the one checked.
    """
    der = await _pinned_certificate(config) if config.tls is TlsMode.PIN else None
    loop = asyncio.get_running_loop()
    return await loop.run_in_executor(None, _build, config, der)


def _build(config: ConnectionConfig, pinned: bytes | None) -> ssl.SSLContext:
    """Make the context (blocking: reads the system CAs and the PEM files)."""
    if config.tls is TlsMode.VERIFY:
        context = ssl.create_default_context()
    else:
        context = ssl.SSLContext(ssl.PROTOCOL_TLS_CLIENT)
        context.check_hostname = False
        if pinned is None:
            context.verify_mode = ssl.CERT_NONE
        else:
            context.load_verify_locations(cadata=pinned)
            context.verify_flags |= ssl.VERIFY_X509_PARTIAL_CHAIN
    _load(context, str(config.options[CERTIFICATE]), str(config.options[KEY]))
    return context


def _load(context: ssl.SSLContext, certificate: str, key: str) -> None:
    """Load the certificate and key into the context, both through private files (bounded)."""
    with contextlib.ExitStack() as stack:
        paths = []
        for material, option in ((certificate, CERTIFICATE), (key, KEY)):
            if not material.lstrip().startswith("-----BEGIN"):
                try:
                    material = read_pem(material, option)  # noqa: PLW2901
                except MaterialError as err:
                    raise PlcAuthenticationError(
                        f"the client certificate and key cannot be used ({err})"
                    ) from None
            folder = stack.enter_context(tempfile.TemporaryDirectory())  # mode 0700
            path = Path(folder) / "pem"
            path.write_text(material, encoding="ascii", errors="replace")
            paths.append(str(path))
        try:
            context.load_cert_chain(paths[0], paths[1])
        except (ssl.SSLError, OSError, ValueError) as err:
            reason = getattr(err, "reason", None) or getattr(err, "strerror", None) or "unreadable"
            raise PlcAuthenticationError(
                f"the client certificate and key cannot be used ({reason})"
            ) from None


async def _pinned_certificate(config: ConnectionConfig) -> bytes:
    """Return the PLC's certificate (DER) after checking it against the pin."""
    der = await fetch_certificate(config.host, config.port, config.timeout)
    if hashlib.sha256(der).hexdigest() != config.fingerprint.lower():
        raise PlcTlsError("the PLC presented a certificate other than the pinned one")
    return der


def refused_certificate(err: PlcError) -> bool:
    """True when a link error is the PLC's TLS alert about our client certificate."""
    seen: BaseException | None = err
    while seen is not None:
        if isinstance(seen, ssl.SSLError):  # aiohttp's subclasses may carry no reason
            text = f"{getattr(seen, 'reason', None) or ''} {seen}".upper()
            if "ALERT" in text and any(name in text for name in _REFUSALS):
                return True
        seen = seen.__cause__ or seen.__context__
    return False


def pem_options(options: Mapping[str, object]) -> dict[str, str]:
    """Return the checked certificate options (both or neither)."""
    certificate, key = options.get(CERTIFICATE) or "", options.get(KEY) or ""
    if not certificate and not key:
        return {}
    if not certificate:
        raise MaterialError("a client key needs its certificate", CERTIFICATE)
    if not key:
        raise MaterialError("a client certificate needs its key", KEY)
    return {CERTIFICATE: check_material(certificate, CERTIFICATE), KEY: check_material(key, KEY)}
