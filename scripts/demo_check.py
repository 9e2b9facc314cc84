"""Check the demo as a new user meets it: scripts/develop, onboarding, the integrations page.

Starts scripts/develop on a throwaway configuration (inside the work tree, where the demo's
Python can see it) and free ports, completes onboarding through the HTTP and websocket calls
the frontend makes, waits for Home Assistant to finish starting, loads what the frontend loads
first and the integrations page, then takes each simulator through a new user's first steps
(scripts/demo_plcs.py: add the PLC, add a device with a point, read it, write it; import the
machines and drive each entity, seeing the PLC change), and fails on
any of those steps, on any integration onboarding set up that did not load, and on any missing
module, failed setup or deprecated use by PLC Bridge in the log. Always stops what it started,
within a bounded time.
Standard library only: it runs with the machine's own python3.

    python3 scripts/demo_check.py
"""

from __future__ import annotations

from collections.abc import Callable
import contextlib
import json
import os
from pathlib import Path
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from typing import Any
import urllib.error

from demo_plcs import JOURNEYS, journey
from hass_client import CLIENT_ID, Hass, Socket

ROOT = Path(__file__).resolve().parent.parent
CONFIG = ROOT / ".demo-check"
START_TIMEOUT = 300.0
"""Seconds for scripts/develop to bring Home Assistant up (a cold .venv-demo is made first)."""
RUNNING_TIMEOUT = 180.0
"""Seconds for Home Assistant to finish starting once onboarded."""
ONBOARDED = ("google_translate", "met", "radio_browser", "shopping_list")
"""What the core config step adds (components/onboarding/views.py); met needs a location."""
FAILED = ("setup_error", "migration_error", "failed_unload")
STARTING = ("not_loaded", "setup_in_progress")
FRONTEND_START = ("auth/current_user", "get_config", "get_states", "get_services", "get_panels")


def free_port() -> int:
    """Return a TCP port nobody listens on now."""
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return int(sock.getsockname()[1])


def onboard(hass: Hass) -> None:
    """Walk the onboarding steps as the frontend does: owner, location, analytics, integrations."""
    user = {"name": "Demo", "username": "demo", "password": "demo-password-1", "language": "en"}
    hass.tokens(
        hass.call("POST", "/api/onboarding/users", {"client_id": CLIENT_ID, **user})["auth_code"]
    )
    ws = Socket(hass)
    try:
        ws.call(
            "config/core/update",
            latitude=52.3731,
            longitude=4.8922,
            elevation=0,
            unit_system="metric",
            time_zone="Europe/Amsterdam",
            currency="EUR",
            country="NL",
        )
    finally:
        ws.close()
    hass.call("POST", "/api/onboarding/core_config", {})
    hass.call("POST", "/api/onboarding/analytics", {})
    redirect = {"client_id": CLIENT_ID, "redirect_uri": CLIENT_ID}
    hass.tokens(hass.call("POST", "/api/onboarding/integration", redirect)["auth_code"])


def entry_states(ws: Socket) -> dict[str, dict[str, Any]]:
    """Return the config entries by id, as the integrations page asks for them."""
    return {entry["entry_id"]: entry for entry in ws.call("config_entries/get")}


def wait_for(ready: Callable[[], bool], timeout: float) -> bool:
    """Poll ready() once a second until it is true or time runs out; return the last answer."""
    deadline = time.monotonic() + timeout
    while not (answer := ready()) and time.monotonic() < deadline:
        time.sleep(1)
    return answer


def frontend(hass: Hass, ws: Socket) -> list[str]:
    """Return what keeps the frontend from loading: its first calls and the integrations page."""
    problems = []
    for kind in FRONTEND_START:
        try:
            ws.call(kind)
        except RuntimeError as err:  # the frontend would stay on "Loading data"
            problems.append(f"the frontend cannot load: {err}")
    if "<html" not in str(hass.call("GET", "/config/integrations/dashboard")).lower():
        problems.append("the integrations page did not load")
    return problems


def integrations(hass: Hass, ws: Socket) -> list[str]:
    """Return what failed: integrations onboarding added, and each simulator's first steps."""

    def settled() -> bool:
        """Tell whether every onboarded integration has an entry that is not starting."""
        states = {entry["domain"]: entry["state"] for entry in entry_states(ws).values()}
        return all(states.get(domain, "") not in ("", *STARTING) for domain in ONBOARDED)

    # A service on the internet (met, radio_browser) may wait to retry: not so a broken setup.
    wait_for(settled, 60)
    entries = entry_states(ws).values()
    domains = {entry["domain"] for entry in entries}
    problems = [f"onboarding did not add {name}" for name in ONBOARDED if name not in domains]
    problems += [
        f"{entry['domain']} is {entry['state']}: {entry.get('reason')}"
        for entry in entries
        if entry["state"] in FAILED
    ]
    simulators = [
        json.loads(line)
        for line in (CONFIG / ".simulators.json").read_text().splitlines()
        if line.strip()
    ]
    if len(simulators) < len(JOURNEYS):
        problems.append(f"the demo started {len(simulators)} simulators, not {len(JOURNEYS)}")
    for sim in simulators:
        problems += journey(hass, ws, sim)
    return problems


def check(hass: Hass) -> list[str]:
    """Return what is wrong with the onboarded demo (nothing, when all is well)."""
    ws = Socket(hass)
    try:
        if wait_for(lambda: ws.call("get_config")["state"] == "RUNNING", RUNNING_TIMEOUT):
            problems = frontend(hass, ws) + integrations(hass, ws)
        else:
            problems = [f"Home Assistant did not finish starting within {RUNNING_TIMEOUT:.0f} s"]
    finally:
        ws.close()
    log = (CONFIG / "home-assistant.log").read_text(errors="replace")
    return problems + [
        line
        for line in log.splitlines()
        if "ModuleNotFoundError" in line or "Setup failed for" in line or deprecated_use(line)
    ]


def deprecated_use(line: str) -> bool:
    """True for a log line where Home Assistant reports that PLC Bridge uses a deprecated API.

    Home Assistant words it two ways: "Detected that custom integration 'plc_bridge' ..."
    (helpers/frame.py) and "custom_components.plc_bridge.climate::PlcClimate provides the
    deprecated ..., this will stop working in Home Assistant ..." (helpers/deprecation.py).
    """
    ours = "'plc_bridge'" in line or "custom_components.plc_bridge" in line
    return ours and ("deprecated" in line or "stop working" in line)


def leftovers() -> list[int]:
    """Return the processes still running on the throwaway configuration."""
    found: list[int] = []
    for process in Path("/proc").iterdir() if Path("/proc").is_dir() else ():
        try:
            if (
                process.name.isdigit()
                and str(CONFIG).encode() in (process / "cmdline").read_bytes()
            ):
                found.append(int(process.name))
        except OSError:
            pass
    return found


def stop(develop: subprocess.Popen[bytes]) -> None:
    """Stop scripts/develop as Ctrl-C does, then anything of the demo that lingers."""
    with contextlib.suppress(ProcessLookupError):  # it may have ended on its own, with its group
        os.killpg(develop.pid, signal.SIGINT)
    try:
        develop.wait(timeout=90)
    except subprocess.TimeoutExpired:
        os.killpg(develop.pid, signal.SIGKILL)
        develop.wait()
    for signum in (signal.SIGTERM, signal.SIGKILL):
        for pid in leftovers():
            with contextlib.suppress(ProcessLookupError):
                os.kill(pid, signum)
        wait_for(lambda: not leftovers(), 10)


def serving(hass: Hass, develop: subprocess.Popen[bytes]) -> bool:
    """Tell whether Home Assistant answers, or scripts/develop has ended without it."""
    try:
        hass.call("GET", "/manifest.json")
    except (urllib.error.URLError, ConnectionError):
        return develop.poll() is not None
    return True


def main() -> int:
    """Run the demo, check it, stop it; print a closing line."""
    shutil.rmtree(CONFIG, ignore_errors=True)
    hass = Hass(free_port())
    env = {
        **os.environ,
        "PLC_BRIDGE_DEMO_CONFIG": str(CONFIG),
        "PLC_BRIDGE_DEMO_PORT": str(hass.port),
        "PLC_BRIDGE_DEMO_SIMULATOR_PORT": "0",
    }
    started = time.monotonic()
    with tempfile.TemporaryFile() as output:
        develop = subprocess.Popen(
            [str(ROOT / "scripts" / "develop")],
            env=env,
            stdin=subprocess.DEVNULL,
            stdout=output,
            stderr=subprocess.STDOUT,
            start_new_session=True,
        )
        try:
            up = wait_for(lambda: serving(hass, develop), START_TIMEOUT)
            if not up or develop.poll() is not None:
                problems = ["scripts/develop did not bring Home Assistant up"]
            else:
                print(f"demo: Home Assistant up in {time.monotonic() - started:.0f} s", flush=True)
                onboard(hass)
                problems = check(hass)
        except Exception as err:  # any failure of the check is reported as one
            problems = [f"{type(err).__name__}: {err}"]
        finally:
            stop(develop)
        output.seek(0)
        said = output.read().decode(errors="replace")
    for problem in problems:
        print(f"demo: {problem}")
    if problems:
        log = CONFIG / "home-assistant.log"
        print(said[-3000:], log.read_text(errors="replace")[-5000:] if log.exists() else "")
    else:
        shutil.rmtree(CONFIG, ignore_errors=True)
    print(f"demo: checked in {time.monotonic() - started:.0f} s")
    print(f"demo: {0 if problems else 1} passed, {1 if problems else 0} failed")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
