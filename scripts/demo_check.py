"""Check the demo as a new user meets it: scripts/develop, onboarding, the integrations page.

Starts scripts/develop on a throwaway configuration (inside the work tree, where the demo's
Python can see it) and a free port, completes onboarding through the same HTTP API the
frontend uses, loads the integrations page, adds the S7 simulator as a PLC through the config
flow API, and fails on any integration that onboarding set up but that did not load. Always
stops what it started. Standard library only: it runs with the machine's own python3.

    python3 scripts/demo_check.py
"""

from __future__ import annotations

import json
import os
from pathlib import Path
import shutil
import signal
import socket
import subprocess
import sys
import time
from typing import Any
import urllib.error
import urllib.parse
import urllib.request

ROOT = Path(__file__).resolve().parent.parent
CONFIG = ROOT / ".demo-check"
CLIENT_ID = "http://127.0.0.1/"
START_TIMEOUT = 300.0
"""Seconds for scripts/develop to bring Home Assistant up (a cold .venv-demo is made first)."""
ONBOARDED = ("google_translate", "met", "radio_browser", "shopping_list")


def free_port() -> int:
    """Return a TCP port nobody listens on now."""
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return int(sock.getsockname()[1])


class Hass:
    """A few calls of Home Assistant's HTTP API."""

    def __init__(self, port: int) -> None:
        """Talk to the Home Assistant on this port."""
        self.base = f"http://127.0.0.1:{port}"
        self.token = ""

    def call(self, method: str, path: str, body: Any = None, *, form: bool = False) -> Any:
        """Send one request; return the decoded JSON answer (or the text)."""
        headers = {"Authorization": f"Bearer {self.token}"} if self.token else {}
        data = None
        if body is not None and form:
            data = urllib.parse.urlencode(body).encode()
            headers["Content-Type"] = "application/x-www-form-urlencoded"
        elif body is not None:
            data = json.dumps(body).encode()
            headers["Content-Type"] = "application/json"
        request = urllib.request.Request(self.base + path, data, headers, method=method)
        with urllib.request.urlopen(request, timeout=30) as answer:
            text = answer.read().decode()
        try:
            return json.loads(text)
        except json.JSONDecodeError:
            return text


def onboard(hass: Hass) -> None:
    """Create the owner, get a token, finish the core config, analytics and integration steps."""
    user = hass.call(
        "POST",
        "/api/onboarding/users",
        {
            "client_id": CLIENT_ID,
            "name": "Demo",
            "username": "demo",
            "password": "demo-password-1",
            "language": "en",
        },
    )
    tokens = hass.call(
        "POST",
        "/auth/token",
        {"grant_type": "authorization_code", "code": user["auth_code"], "client_id": CLIENT_ID},
        form=True,
    )
    hass.token = tokens["access_token"]
    hass.call("POST", "/api/onboarding/core_config", {})
    hass.call("POST", "/api/onboarding/analytics", {})
    hass.call(
        "POST", "/api/onboarding/integration", {"client_id": CLIENT_ID, "redirect_uri": CLIENT_ID}
    )


def add_s7_plc(hass: Hass) -> dict[str, Any]:
    """Add the S7 simulator through the config flow API, as the dialog would; return the entry."""
    simulators = [
        json.loads(line)
        for line in (CONFIG / ".simulators.json").read_text().splitlines()
        if line.strip()
    ]
    s7 = next(sim for sim in simulators if sim["vendor"] == "s7")
    flow = hass.call("POST", "/api/config/config_entries/flow", {"handler": "plc_bridge"})
    step = f"/api/config/config_entries/flow/{flow['flow_id']}"
    flow = hass.call("POST", step, {"vendor": "s7"})
    flow = hass.call("POST", step, {"host": s7["host"], "port": s7["port"]})
    if flow.get("step_id") == "s7_rack_slot":  # the second page: how the CPU is addressed
        flow = hass.call("POST", step, s7.get("options", {}))
    if flow.get("step_id") == "name":
        flow = hass.call("POST", step, {"name": "Demo S7"})
    assert flow.get("type") == "create_entry", flow
    return dict(flow["result"])


def check(hass: Hass) -> list[str]:
    """Return what is wrong with the onboarded demo (nothing, when all is well)."""
    problems: list[str] = []
    page = hass.call("GET", "/config/integrations/dashboard")
    if "<html" not in str(page).lower():
        problems.append("the integrations page did not load")
    deadline = time.monotonic() + 60
    while True:
        entries = hass.call("GET", "/api/config/config_entries/entry")
        states = {entry["domain"]: entry["state"] for entry in entries}
        pending = [d for d in ONBOARDED if states.get(d) in ("not_loaded", "setup_in_progress")]
        if not pending or time.monotonic() > deadline:
            break
        time.sleep(1)
    # A service on the internet (radio_browser) may wait to retry: not so a broken setup.
    problems += [
        f"{entry['domain']} is {entry['state']}: {entry.get('reason')}"
        for entry in entries
        if entry["state"] in ("setup_error", "migration_error", "failed_unload")
    ]
    added = add_s7_plc(hass)
    time.sleep(3)
    entries = {
        entry["entry_id"]: entry for entry in hass.call("GET", "/api/config/config_entries/entry")
    }
    if entries[added["entry_id"]]["state"] != "loaded":
        problems.append(f"the S7 PLC did not load: {entries[added['entry_id']]}")
    log = (CONFIG / "home-assistant.log").read_text(errors="replace")
    problems += [
        line
        for line in log.splitlines()
        if "ModuleNotFoundError" in line or "Setup failed for" in line
    ]
    return problems


def main() -> int:
    """Run the demo, check it, stop it; print a closing line."""
    shutil.rmtree(CONFIG, ignore_errors=True)
    port = free_port()
    env = {**os.environ, "PLC_BRIDGE_DEMO_CONFIG": str(CONFIG), "PLC_BRIDGE_DEMO_PORT": str(port)}
    started = time.monotonic()
    develop = subprocess.Popen(
        [str(ROOT / "scripts" / "develop")],
        env=env,
        stdin=subprocess.DEVNULL,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        start_new_session=True,
    )
    hass = Hass(port)
    problems: list[str] = []
    try:
        while True:
            try:
                hass.call("GET", "/manifest.json")
                break
            except (urllib.error.URLError, ConnectionError):
                if develop.poll() is not None or time.monotonic() - started > START_TIMEOUT:
                    problems.append("scripts/develop did not bring Home Assistant up")
                    break
                time.sleep(1)
        if not problems:
            print(f"demo: Home Assistant up in {time.monotonic() - started:.0f} s", flush=True)
            onboard(hass)
            problems = check(hass)
    except Exception as err:  # any failure of the check is reported as one
        problems.append(f"{type(err).__name__}: {err}")
    finally:
        os.killpg(develop.pid, signal.SIGINT)
        try:
            output, _ = develop.communicate(timeout=60)
        except subprocess.TimeoutExpired:
            os.killpg(develop.pid, signal.SIGKILL)
            output, _ = develop.communicate()
    for problem in problems:
        print(f"demo: {problem}")
    if problems:
        print(output[-3000:])
        log = CONFIG / "home-assistant.log"
        if log.exists():
            print(log.read_text(errors="replace")[-5000:])
    else:
        shutil.rmtree(CONFIG, ignore_errors=True)
    print(f"demo: {0 if problems else 1} passed, {1 if problems else 0} failed")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
