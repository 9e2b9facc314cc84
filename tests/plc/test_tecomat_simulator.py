"""The TecoApi simulator itself: the services and every error of 3.7 a client can provoke."""

from __future__ import annotations

import hashlib
import json
import re
from typing import Any

import aiohttp
import pytest
from yarl import URL

from custom_components.plc_bridge.plc.vendors.tecomat.api import basic_authorization
from simulators.tecomat import DEFAULT_PASSWORD, DEFAULT_USER, TecomatSimulator
from simulators.tecomat.values import render

AUTH = {"Authorization": basic_authorization(DEFAULT_USER, DEFAULT_PASSWORD)}


async def call(
    sim: TecomatSimulator, method: str, target: str, body: bytes | None = None, **kwargs: Any
) -> tuple[int, Any]:
    """Send one request verbatim; return the status and the JSON body (None when empty)."""
    url = URL(f"http://{sim.host}:{sim.port}{target}", encoded=True)
    kwargs.setdefault("headers", AUTH)
    async with (
        aiohttp.ClientSession() as session,
        session.request(method, url, data=body, **kwargs) as response,
    ):
        raw = await response.read()
        return response.status, json.loads(raw) if raw else None


def code(answer: Any) -> str:
    """Return the error code of an error answer."""
    return str(answer["error"]["code"])


@pytest.mark.parametrize(
    ("method", "target", "body", "expected"),
    [
        ("GET", "/TecoApi/GetObject", None, "400.001"),
        ("GET", "/TecoApi/GetObject?plcName&&plcType", None, "400.003"),
        ("GET", "/TecoApi/GetObject?nothing", None, "400.005"),
        ("GET", "/TecoApi/GetObject?1bad", None, "400.005"),
        ("GET", "/TecoApi/GetObject?" + "a" * 129, None, "400.007"),
        ("GET", "/TecoApi/GetObject?" + "plcName&" * 30 + "x", None, "414.000"),
        ("PUT", "/TecoApi/PutObject", b'{"' + b"a" * 65 + b'": 1}', "400.008"),
        ("PUT", "/TecoApi/PutObject", b'{"plcType": 1.5E3}', "400.009"),
        ("PUT", "/TecoApi/PutObject", '{"plcDesc": "č"}'.encode(), "400.009"),
        ("PUT", "/TecoApi/PutObject", b"[1]", "400.009"),
        ("PUT", "/TecoApi/PutObject", b'{"plcType": ', "400.009"),
        ("PUT", "/TecoApi/PutObject", b'{"a":' * 33 + b"1" + b"}" * 33, "400.009"),
        ("PUT", "/TecoApi/PutObject", b'{"plcDesc": "' + b"x" * 256 + b'"}', "400.009"),
        ("PUT", "/TecoApi/PutObject", b'{"plcType": 70000}', "400.015"),
        ("PUT", "/TecoApi/PutObject", b'{"myObject": 1}', "400.015"),
        ("PUT", "/TecoApi/PutObject", b'{"nope": {"x": 1}}', "400.005"),
        ("PUT", "/TecoApi/PutObject", b'{"myObject": {"1x": 1}}', "400.005"),
        ("PUT", "/TecoApi/PutObject", b'{"arr1": ["a","b","c","d","e","f","g"]}', "400.005"),
        ("GET", "/TecoApi/GetList?listType=tree", None, "400.016"),
        ("GET", "/TecoApi/GetList?=struct", None, "400.017"),
        ("GET", "/TecoApi/GetList?depth=1", None, "400.018"),
        ("GET", "/TecoApi/GetList?listType=", None, "400.019"),
        ("GET", "/TecoApi/SetObject?=1", None, "400.017"),
        ("GET", "/TecoApi/SetObject?plcType", None, "400.019"),
        ("GET", "/TecoApi/GetData", None, "501.013"),
        ("PUT", "/TecoApi/GetObject?plcName", b"{}", "501.013"),
        ("GET", "/TecoApi/", None, "400.014"),
    ],
)
async def test_errors(
    basic_sim: TecomatSimulator, method: str, target: str, body: bytes | None, expected: str
) -> None:
    status, answer = await call(basic_sim, method, target, body)
    assert code(answer) == expected
    assert status == int(expected[:3])


async def test_variable_limits(basic_sim: TecomatSimulator) -> None:
    basic_sim.max_variables = 2
    status, answer = await call(basic_sim, "GET", "/TecoApi/GetObject?plcName&plcType&plcDesc")
    assert (status, code(answer)) == (413, "413.002")
    assert answer["error"]["message"] == (
        "Too many variables in one request (requested: 3, allowed: 2)"
    )
    basic_sim.max_variables = 12
    status, answer = await call(basic_sim, "GET", "/TecoApi/GetObject?myObject")
    assert (status, code(answer)) == (413, "413.004")
    assert answer["error"]["message"] == "Too many variables (maximum is 12)"
    body = json.dumps({"arr3": [[[1] * 4] * 3] * 2}).encode()
    assert code((await call(basic_sim, "PUT", "/TecoApi/PutObject", body))[1]) == "413.004"
    basic_sim.max_variables = 13
    status, answer = await call(basic_sim, "GET", "/TecoApi/GetObject?myObject")
    assert status == 200
    assert answer["myObject"]["favorites"]["color"] == '"Blue"'


async def test_get_object_answers(basic_sim: TecomatSimulator) -> None:
    target = (
        "/TecoApi/GetObject?myObject.first&MYOBJECT.favorites.sport&arr2[1][3]&arr1[2]&arr2[2,0]"
    )
    status, answer = await call(basic_sim, "GET", target)
    assert status == 200
    assert answer == {
        "myObject": {"first": "John", "favorites": {"sport": "Soccer"}},
        "arr2[1][3]": 1.3,
        "arr1[2]": "two",
        "arr2[2][0]": 2.0,
    }
    _status, whole = await call(basic_sim, "GET", "/TecoApi/GetObject?plcData&myObject.favorites")
    assert whole["plcData"]["varTime"] == "120:02:03.450"
    assert whole["plcData"]["varDT"] == "2014-05-11T11:22:33.456Z"
    assert whole["plcData"]["varDate"] == "2015-06-17"
    async with aiohttp.ClientSession() as session:
        url = f"http://{basic_sim.host}:{basic_sim.port}/TecoApi/GetObject?plcData.varReal"
        async with session.get(url, headers=AUTH) as response:
            assert await response.text() == '{"plcData":{"varReal":1000.000000}}'
            assert response.headers["Server"].startswith("TecoApi/1.0.0")


async def test_lists(basic_sim: TecomatSimulator) -> None:
    _status, struct = await call(basic_sim, "GET", "/TecoApi/GetList")
    assert struct["plcName"] == {}
    assert struct["Main"]["myObject3"] == {}
    _status, array = await call(basic_sim, "GET", "/TecoApi/GetList?listType=array")
    assert array[0] == {"plcName": {}}
    assert len(array) == len(struct)


async def test_set_object(basic_sim: TecomatSimulator) -> None:
    target = '/TecoApi/SetObject?plcType=1005&plcDesc="testing is funny"&arr1[5]=five'
    status, answer = await call(basic_sim, "GET", target.replace(" ", "%20").replace('"', "%22"))
    assert (status, answer) == (200, None)
    assert basic_sim.get("plcType") == 1005
    assert basic_sim.get("plcDesc") == "testing is funny"
    assert basic_sim.get("arr1[5]") == "five"
    status, _ = await call(basic_sim, "GET", "/TecoApi/SetObject?myObject.registered=true")
    assert status == 200
    assert basic_sim.get("myObject.registered") is True


async def test_put_object_whole_structures(basic_sim: TecomatSimulator) -> None:
    body = {
        "myObject": {"first": "Mia", "interests": ["Reading", "Cooking", "Traveling"]},
        "arr2": [[0.0, 0.11, 0.22, 0.33], [11.0, 11.11, 11.22, 11.33], [22, 22.11, 22.22, 22.33]],
        "myObject.favorites.color": "Red",
    }
    status, _ = await call(basic_sim, "PUT", "/TecoApi/PutObject", json.dumps(body).encode())
    assert status == 204
    assert basic_sim.get("myObject.interests[2]") == "Traveling"
    assert basic_sim.get("myObject.favorites.color") == "Red"
    assert basic_sim.get("arr2[2][0]") == 22.0
    status, answer = await call(
        basic_sim, "PUT", "/TecoApi/PutObject", b'{"plcName": "x" , "plcType": -1}'
    )
    assert code(answer) == "400.015"
    assert basic_sim.get("plcName") == "myFoxtrot"  # nothing is written when one value fails


@pytest.mark.parametrize(
    ("variable", "value"),
    [
        ("plcData.varBool0", 2),
        ("plcData.varReal", 10**39),
        ("plcData.varTime", "600:00:00.000"),
        ("plcData.varTod", "24:00:00.000"),
        ("plcData.varDate", "1969-12-31"),
        ("plcData.varDate", "2015-6-17"),
        ("plcData.varDT", "1969-12-31T23:59:59.000Z"),
        ("plcData.varDT", "2015-02-30T00:00:00.000Z"),
        ("plcData.varString", 5),
        ("plcData.varStringArray[0]", "ninechars"),
    ],
)
async def test_values_that_do_not_fit(
    basic_sim: TecomatSimulator, variable: str, value: Any
) -> None:
    body = json.dumps({variable: value}).encode()
    status, answer = await call(basic_sim, "PUT", "/TecoApi/PutObject", body)
    assert (status, code(answer)) == (400, "400.015")
    assert f"to variable '{variable}'" in answer["error"]["message"]


@pytest.mark.parametrize(
    ("state", "expected"),
    [
        ("missing", "500.010"),
        ("too_big", "500.011"),
        ("unreadable", "500.012"),
        ("empty", "400.006"),
    ],
)
async def test_program_faults(basic_sim: TecomatSimulator, state: str, expected: str) -> None:
    if state == "empty":
        basic_sim.variables.clear()
    else:
        basic_sim.public_file = state
    assert code((await call(basic_sim, "GET", "/TecoApi/GetList"))[1]) == expected
    assert (await call(basic_sim, "GET", "/TecoApi/GetInfo"))[0] == 200


async def test_authentication_answers(basic_sim: TecomatSimulator) -> None:
    status, answer = await call(basic_sim, "GET", "/TecoApi/GetInfo", headers={})
    assert (status, code(answer)) == (401, "401.023")
    headers = {"Authorization": "Bearer x"}
    assert code((await call(basic_sim, "GET", "/TecoApi/GetInfo", headers=headers))[1]) == "403.022"
    headers = {"Authorization": "Basic !!"}
    assert code((await call(basic_sim, "GET", "/TecoApi/GetInfo", headers=headers))[1]) == "401.021"


async def test_digest_details() -> None:
    sim = TecomatSimulator(bench=0)
    await sim.start()
    try:
        url = f"http://{sim.host}:{sim.port}/TecoApi/GetInfo"
        async with aiohttp.ClientSession() as session, session.get(url) as response:
            challenge = response.headers["WWW-Authenticate"]
        assert challenge.startswith('Digest realm="TecoApi",qop="auth,auth-int",nonce="')
        fields = dict(re.findall(r'(\w+)="([^"]*)"', challenge))
        nonce, opaque = fields["nonce"], fields["opaque"]

        def md5(*parts: str) -> str:
            return hashlib.md5(":".join(parts).encode(), usedforsecurity=False).hexdigest()

        ha1 = md5(DEFAULT_USER, "TecoApi", DEFAULT_PASSWORD)
        rfc2069 = md5(ha1, nonce, md5("GET", "/TecoApi/GetInfo"))
        header = (
            f'Digest username="{DEFAULT_USER}",realm="TecoApi",nonce="{nonce}",'
            f'uri="/TecoApi/GetInfo",response="{rfc2069}",opaque="{opaque}"'
        )
        status, _ = await call(sim, "GET", "/TecoApi/GetInfo", headers={"Authorization": header})
        assert status == 200
        wrong_uri = header.replace('uri="/TecoApi/GetInfo"', 'uri="/TecoApi/GetList"')
        status, answer = await call(
            sim, "GET", "/TecoApi/GetInfo", headers={"Authorization": wrong_uri}
        )
        assert code(answer) == "401.021"
        assert sim.auth.accepted == {"digest without qop": 1}
    finally:
        await sim.stop()


async def test_test_api(basic_sim: TecomatSimulator) -> None:
    with pytest.raises(ValueError, match="does not name"):
        basic_sim.rename("arr1[1]", "x")
    with pytest.raises(TypeError, match="not a member"):
        basic_sim.rename("arr2[1].x", "y")
    with pytest.raises(TypeError, match="not an elementary"):
        basic_sim.var("myObject")
    basic_sim.set("plcType", 7)
    assert basic_sim.get("PLCTYPE") == 7
    with pytest.raises(ValueError, match="digest"):
        TecomatSimulator(auth="ntlm")


def test_animate() -> None:
    sim = TecomatSimulator(bench=0)
    before = render(sim.variables)
    sim.animate(0.0)
    assert render(sim.variables) == before  # the demo starts from the program's values
    outside, inside = "Main.myObject1.value", "Main.myObject2.value"
    last = (sim.get(outside), sim.get(inside))
    for second in range(1, 3601):
        sim.animate(float(second))
        now = (sim.get(outside), sim.get(inside))
        assert all(abs(a - b) <= 0.1001 for a, b in zip(now, last, strict=True))
        last = now
    sim.animate(450.0)
    assert (sim.get(outside), round(sim.get(inside), 3)) == (3.5, 22.5)
    assert sim.get("Boiler.water") == 500  # the demo boiler's water drifts too
    after = render(sim.variables)
    for name in ("myObject1", "myObject2"):
        after["Main"][name]["value"] = before["Main"][name]["value"]
    after["Boiler"]["water"] = before["Boiler"]["water"]
    assert after == before  # nothing else moves
