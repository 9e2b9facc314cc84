"""What every simulator shares: loopback start/stop, optional TLS, a request counter."""

from __future__ import annotations

import datetime as dt
import hashlib
from ipaddress import ip_address
import ssl
import tempfile

from aiohttp import web
from cryptography import x509
from cryptography.hazmat.primitives import hashes, serialization
from cryptography.hazmat.primitives.asymmetric import ec
from cryptography.x509.oid import NameOID


def make_certificate(common_name: str) -> tuple[bytes, bytes]:
    """Return (PEM chain, PEM key) of a leaf certificate signed by a CA made on the spot.

    Like an S7-200 SMART in "internal certificate" mode: the device's own CA, unknown to any
    trust store, so clients must pin or turn verification off.
    """
    now = dt.datetime.now(dt.UTC)
    ca_key = ec.generate_private_key(ec.SECP256R1())
    ca_name = x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, f"{common_name} CA")])
    ca = (
        x509.CertificateBuilder()
        .subject_name(ca_name)
        .issuer_name(ca_name)
        .public_key(ca_key.public_key())
        .serial_number(x509.random_serial_number())
        .not_valid_before(now - dt.timedelta(days=1))
        .not_valid_after(now + dt.timedelta(days=3650))
        .add_extension(x509.BasicConstraints(ca=True, path_length=0), critical=True)
        .sign(ca_key, hashes.SHA256())
    )
    key = ec.generate_private_key(ec.SECP256R1())
    leaf = (
        x509.CertificateBuilder()
        .subject_name(x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, common_name)]))
        .issuer_name(ca_name)
        .public_key(key.public_key())
        .serial_number(x509.random_serial_number())
        .not_valid_before(now - dt.timedelta(days=1))
        .not_valid_after(now + dt.timedelta(days=3650))
        .add_extension(
            x509.SubjectAlternativeName(
                [x509.DNSName("localhost"), x509.IPAddress(ip_address("127.0.0.1"))]
            ),
            critical=False,
        )
        .sign(ca_key, hashes.SHA256())
    )
    chain = leaf.public_bytes(serialization.Encoding.PEM) + ca.public_bytes(
        serialization.Encoding.PEM
    )
    key_pem = key.private_bytes(
        serialization.Encoding.PEM,
        serialization.PrivateFormat.PKCS8,
        serialization.NoEncryption(),
    )
    return chain, key_pem


# cryptography's Rust core remembers the datetime class it first sees; were that first
# certificate made under a test's frozen clock, it would take the frozen class for the real one
# and refuse real datetimes ever after. Make the first one now, at import, with the real class.
make_certificate("localhost")


class HttpSimulator:
    """An aiohttp server on loopback; subclasses add routes in `build_app`.

    `requests` counts every HTTP request that reached the API (what a PLC's CPU pays for).
    """

    tls: bool = False
    common_name: str = "plc-simulator"

    def __init__(self) -> None:
        """Prepare the server; nothing listens until `start`."""
        self.host = "127.0.0.1"
        self.port = 0
        self.requests = 0
        self.peers: set[tuple[str, int]] = set()  # client addresses seen: one per connection
        self.fingerprint: str | None = None
        self._runner: web.AppRunner | None = None
        self._ssl: ssl.SSLContext | None = None

    def build_app(self, app: web.Application) -> None:
        """Add the vendor's routes to the application."""
        raise NotImplementedError

    @web.middleware
    async def _count(self, request: web.Request, handler: web.Handler) -> web.StreamResponse:
        """Count each request, and the connection it came on, before it is handled."""
        self.requests += 1
        if request.transport is not None and (peer := request.transport.get_extra_info("peername")):
            self.peers.add((peer[0], peer[1]))
        return await handler(request)

    def new_certificate(self) -> None:
        """Generate a fresh certificate (a PLC whose certificate was replaced)."""
        self.use_certificate(*make_certificate(self.common_name))

    def use_certificate(self, chain: bytes, key: bytes) -> None:
        """Serve this certificate chain and private key (PEM) from the next start on."""
        with (
            tempfile.NamedTemporaryFile(suffix=".pem") as cert_file,
            tempfile.NamedTemporaryFile(suffix=".pem") as key_file,
        ):
            cert_file.write(chain)
            cert_file.flush()
            key_file.write(key)
            key_file.flush()
            context = ssl.create_default_context(ssl.Purpose.CLIENT_AUTH)
            context.load_cert_chain(cert_file.name, key_file.name)
        der = x509.load_pem_x509_certificates(chain)[0].public_bytes(serialization.Encoding.DER)
        self.fingerprint = hashlib.sha256(der).hexdigest()
        self._ssl = context

    async def start(self, host: str = "127.0.0.1", port: int = 0) -> None:
        """Listen on host:port (port 0 picks a free one, then `self.port` tells which)."""
        if self.tls and self._ssl is None:
            self.new_certificate()
        app = web.Application(middlewares=[self._count])
        self.build_app(app)
        self._runner = web.AppRunner(app, access_log=None)
        await self._runner.setup()
        site = web.TCPSite(self._runner, host, port, ssl_context=self._ssl, reuse_address=True)
        await site.start()
        server = site._server  # aiohttp exposes the bound port only here
        assert server is not None
        self.host = host
        self.port = server.sockets[0].getsockname()[1]

    async def stop(self) -> None:
        """Stop listening and drop every connection."""
        if self._runner is not None:
            await self._runner.cleanup()
            self._runner = None

    async def restart(self) -> None:
        """Stop and start again on the same port (a PLC reboot)."""
        await self.stop()
        await self.start(self.host, self.port)
