"""The client certificate WEB.TLM may ask of a PUT ("client_auth = ssl"), in an SSL context.

The certificate and key come as pasted PEM or as absolute file paths (options
`client_certificate` and `client_key`); an encrypted key is not supported. Nothing here logs or
quotes either of them.
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
    PlcConnectionError,
    PlcError,
    PlcTimeoutError,
    PlcTlsError,
    PlcValueError,
)
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


def check_material(value: object, what: str, marker: str) -> str:
    """Return pasted PEM or an absolute path, stripped; raise PlcValueError (never quoting it)."""
    if not isinstance(value, str):
        raise PlcValueError(f"the {what} is PEM text or a file path")
    text = value.strip()
    if text.startswith("-----BEGIN"):
        if marker not in text or "-----END" not in text:
            raise PlcValueError(f"the {what} is not a PEM {marker.lower()}")
        return text + "\n"
    if not text or "\n" in text or not os.path.isabs(text):
        raise PlcValueError(f"the {what} is pasted PEM text or an absolute file path")
    return text


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
    """Load the certificate and key into the context; pasted PEM goes through private files."""
    with contextlib.ExitStack() as stack:
        paths = []
        for material in (certificate, key):
            if material.lstrip().startswith("-----BEGIN"):
                folder = stack.enter_context(tempfile.TemporaryDirectory())  # mode 0700
                path = Path(folder) / "pem"
                path.write_text(material, encoding="ascii", errors="replace")
                paths.append(str(path))
            else:
                paths.append(material)
        try:
            context.load_cert_chain(paths[0], paths[1])
        except (ssl.SSLError, OSError, ValueError) as err:
            reason = getattr(err, "reason", None) or getattr(err, "strerror", None) or "unreadable"
            raise PlcAuthenticationError(
                f"the client certificate and key cannot be used ({reason})"
            ) from None


async def _pinned_certificate(config: ConnectionConfig) -> bytes:
    """Return the PLC's certificate (DER) after checking it against the pin."""
    probe = ssl.SSLContext(ssl.PROTOCOL_TLS_CLIENT)
    probe.check_hostname = False
    probe.verify_mode = ssl.CERT_NONE
    try:
        async with asyncio.timeout(config.timeout):
            _reader, writer = await asyncio.open_connection(config.host, config.port, ssl=probe)
    except TimeoutError as err:
        raise PlcTimeoutError(f"no answer from {config.host} in time") from err
    except ssl.SSLError as err:
        raise PlcTlsError(f"TLS failed: {err.reason}") from err
    except OSError as err:
        raise PlcConnectionError(f"cannot reach {config.host}:{config.port}: {err}") from err
    try:
        ssl_object = writer.get_extra_info("ssl_object")
        der = ssl_object.getpeercert(binary_form=True) if ssl_object else None
    finally:
        writer.close()
    if not der or hashlib.sha256(der).hexdigest() != config.fingerprint.lower():
        raise PlcTlsError("the PLC presented a certificate other than the pinned one")
    return bytes(der)


def refused_certificate(err: PlcError) -> bool:
    """True when a link error is the PLC's TLS alert about our client certificate."""
    seen: BaseException | None = err
    while seen is not None:
        if isinstance(seen, ssl.SSLError):
            text = f"{seen.reason or ''} {seen}".upper()
            if "ALERT" in text and any(name in text for name in _REFUSALS):
                return True
        seen = seen.__cause__ or seen.__context__
    return False


def pem_options(options: Mapping[str, object]) -> dict[str, str]:
    """Return the checked certificate options (both or neither)."""
    certificate, key = options.get(CERTIFICATE) or "", options.get(KEY) or ""
    if not certificate and not key:
        return {}
    if not certificate or not key:
        raise PlcValueError("a client certificate needs its key, and a key its certificate")
    return {
        CERTIFICATE: check_material(certificate, "client certificate", "CERTIFICATE"),
        KEY: check_material(key, "client key", "PRIVATE KEY"),
    }
