"""PUT authentication by SSL client certificate: reads work without, writes need a trusted one."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import pytest

from custom_components.plc_bridge.plc import PlcAuthenticationError, PlcValueError, Point, TlsMode
from custom_components.plc_bridge.plc.vendors.softplc import SoftplcClient
from simulators.__main__ import keep_certificate
from simulators.softplc import SoftplcSimulator

if TYPE_CHECKING:
    from .softplc_fixtures import ConfigFactory


def options(sim: SoftplcSimulator, *, trusted: bool = True) -> dict[str, str | int | bool]:
    """Return checked vendor options with a client certificate the PLC trusts (or not)."""
    certificate, key = sim.client_certificate(trusted=trusted)
    return SoftplcClient.validate_options({"client_certificate": certificate, "client_key": key})


@pytest.mark.parametrize("tls", [TlsMode.PIN, TlsMode.OFF])
async def test_put_with_trusted_certificate(
    softplc_tls_sim: SoftplcSimulator, softplc_settings: ConfigFactory, tls: TlsMode
) -> None:
    """A trusted certificate writes; the pin is still checked."""
    client = SoftplcClient(
        softplc_settings(softplc_tls_sim, tls=tls, options=options(softplc_tls_sim))
    )
    try:
        await client.connect()
        results = await client.write({Point("N7:0", "INT"): 77})
        assert results[Point("N7:0", "INT")].value == 77
        assert softplc_tls_sim.files["N", 7].words[0] == 77
    finally:
        await client.close()


async def test_reads_without_certificate_writes_refused(
    softplc_tls_sim: SoftplcSimulator, softplc_settings: ConfigFactory
) -> None:
    """Without a certificate reads work and a write says a certificate is needed."""
    client = SoftplcClient(softplc_settings(softplc_tls_sim))
    try:
        await client.connect()
        assert (await client.read([Point("N7:3", "")])).values[Point("N7:3", "")].value == 3
        with pytest.raises(PlcAuthenticationError, match="only with a client certificate"):
            await client.write({Point("N7:0", "INT"): 1})
    finally:
        await client.close()


async def connect_and_write(client: SoftplcClient) -> None:
    """Connect and write one word (the handshake or the PUT refuses the certificate)."""
    await client.connect()
    await client.write({Point("N7:0", "INT"): 1})


@pytest.mark.parametrize("check", ["request", "handshake"])
async def test_untrusted_certificate(softplc_settings: ConfigFactory, check: str) -> None:
    """A certificate the PLC does not trust is an authentication error, refused either way."""
    sim = SoftplcSimulator(tls=True, put_auth=True)
    sim.cert_check = check
    await sim.start()
    client = SoftplcClient(softplc_settings(sim, options=options(sim, trusted=False)))
    try:
        with pytest.raises(PlcAuthenticationError, match="certificate"):
            await connect_and_write(client)
        assert sim.files["N", 7].words[0] == 0
    finally:
        await client.close()
        await sim.stop()


async def test_wrong_pin_refused(
    softplc_tls_sim: SoftplcSimulator, softplc_settings: ConfigFactory
) -> None:
    """With a client certificate the pin is checked by the client's own context."""
    from custom_components.plc_bridge.plc import PlcTlsError

    config = softplc_settings(
        softplc_tls_sim, fingerprint="00" * 32, options=options(softplc_tls_sim)
    )
    client = SoftplcClient(config)
    try:
        with pytest.raises(PlcTlsError):
            await client.connect()
    finally:
        await client.close()


@pytest.mark.parametrize(
    "settings",
    [
        {"client_certificate": "-----BEGIN CERTIFICATE-----\nxx"},
        {"client_certificate": "relative/cert.pem", "client_key": "/abs/key.pem"},
        {"client_certificate": "-----BEGIN CERTIFICATE-----\n-----END", "client_key": "nokey"},
    ],
)
def test_options_checked(settings: dict[str, str]) -> None:
    """A certificate without its key, or neither PEM nor an absolute path, is refused."""
    with pytest.raises(PlcValueError):
        SoftplcClient.validate_options(settings)


async def test_unusable_key_is_authentication_error(
    softplc_tls_sim: SoftplcSimulator, softplc_settings: ConfigFactory
) -> None:
    """A key that is not the certificate's is reported without quoting either."""
    certificate, _key = softplc_tls_sim.client_certificate()
    _other, key = softplc_tls_sim.client_certificate()
    settings = SoftplcClient.validate_options(
        {"client_certificate": certificate, "client_key": key}
    )
    client = SoftplcClient(softplc_settings(softplc_tls_sim, options=settings))
    try:
        with pytest.raises(PlcAuthenticationError) as raised:
            await client.connect()
        assert "PRIVATE" not in str(raised.value)
    finally:
        await client.close()


async def test_demo_client_certificate(tmp_path: Path, softplc_settings: ConfigFactory) -> None:
    """The demo's simulator: HTTPS, PUT authentication, a client certificate written into the
    demo folder; an entry storing those paths still writes after the simulator restarts."""
    fingerprints = []
    for _start in range(2):
        sim = SoftplcSimulator(**SoftplcSimulator.DEMO_OPTIONS)
        keep_certificate(sim, tmp_path, "softplc")
        sim.keep_client_certificate(tmp_path)
        assert (tmp_path / "softplc-client.key").stat().st_mode & 0o077 == 0
        assert set(sim.form_fields) == {"Client certificate", "Client key"}
        await sim.start()
        fingerprints.append(sim.fingerprint)
        options = SoftplcClient.validate_options(
            {
                "client_certificate": sim.form_fields["Client certificate"],
                "client_key": sim.form_fields["Client key"],
            }
        )
        client = SoftplcClient(softplc_settings(sim, options=options))
        try:
            await client.connect()
            await client.check_certificate()
            results = await client.write({Point("N7:0", "INT"): 5})
            assert results[Point("N7:0", "INT")].value == 5
        finally:
            await client.close()
            await sim.stop()
    assert fingerprints[0] == fingerprints[1]
