"""/docs in a real browser: Swagger UI, served by the service itself, runs one process's
example with "Try it out" as a user would, and shows the answer the JSON API gives."""

from __future__ import annotations

import json
import re
from typing import Any

import numpy as np
import pytest

from tests.browser.test_workbench import browser_errors, wait_until
from tests.live import LiveServer

pytestmark = pytest.mark.e2e

PROCESS = "alignment.rigid"
PATH = f"/processes/{PROCESS}/execution"


def numbers(doc: Any, prefix: str = "") -> dict[str, float]:
    """Every number of a JSON document by its path (``transform.0.3``); booleans apart."""
    out: dict[str, float] = {}
    if isinstance(doc, dict):
        for key, value in doc.items():
            out.update(numbers(value, f"{prefix}.{key}" if prefix else str(key)))
    elif isinstance(doc, list):
        for i, value in enumerate(doc):
            out.update(numbers(value, f"{prefix}.{i}"))
    elif isinstance(doc, (int, float)) and not isinstance(doc, bool):
        out[prefix] = float(doc)
    return out


def within(browser: Any, element: Any, css: str, timeout: float = 10.0) -> Any:
    """The first element matching ``css`` inside ``element``, once there is one (Swagger UI
    renders an operation's parts after it opens, and its response after it arrives)."""
    from selenium.webdriver.support.ui import WebDriverWait

    found = WebDriverWait(browser, timeout, poll_frequency=0.05).until(
        lambda _: element.find_elements("css selector", css))
    return found[0]


def test_try_it_out_runs_the_example(browser: Any, server: LiveServer, http: Any,
                                     shot: Any) -> None:
    browser.get(f"{server.url}/docs")
    # the family's tag, then the process's own execute operation, as a user clicks them
    tag = wait_until(browser, "return document.querySelector('.opblock-tag[data-tag=alignment]')",
                     30)
    tag.click()
    summary = wait_until(browser, "return document.querySelector("
                         f"'.opblock-summary-path[data-path=\"{PATH}\"]')", 10)
    browser.execute_script("arguments[0].scrollIntoView({block: 'center'})", summary)
    summary.click()
    block = wait_until(browser, "return [...document.querySelectorAll('.opblock.is-open')].find("
                       f"(b) => b.querySelector('[data-path=\"{PATH}\"]'))", 10)
    within(browser, block, "button.try-out__btn").click()

    # the body is the example of the process's execute operation in the OpenAPI document
    textarea = within(browser, block, "textarea.body-param__text")
    body = json.loads(textarea.get_attribute("value"))
    content = http.get("/openapi.json").json()["paths"][PATH]["post"]["requestBody"]["content"]
    assert body == next(iter(content["application/json"]["examples"].values()))["value"]
    headers = {i.get_attribute("placeholder"): i.get_attribute("value")
               for i in block.find_elements("css selector", ".parameters input")}
    prefer = headers.get("Prefer") or None

    within(browser, block, "button.execute").click()
    response = within(browser, block, ".live-responses-table tr.response", 60)
    status = response.find_element("css selector", ".response-col_status").text.strip()
    answer = response.find_element("css selector", ".response-col_description")
    shown = within(browser, answer, ".highlight-code pre")
    browser.execute_script("arguments[0].scrollIntoView({block: 'center'})", shown)
    shot()
    # Swagger sends the operation's example header too, Prefer: wait=60: the results, at once
    assert status == "200", (status, prefer)
    results = json.loads(shown.get_attribute("textContent"))

    # the same request through the JSON API, independently of the page
    request_headers = {"Content-Type": "application/json"}
    if prefer:
        request_headers["Prefer"] = prefer
    api = http.post(PATH, content=json.dumps(body), headers=request_headers)
    assert api.status_code == 200, api.text
    expected = api.json()
    got, want = numbers(results), numbers(expected)
    assert set(got) == set(want)
    assert want, "the results hold no number"
    keys = sorted(want)
    assert np.allclose([got[k] for k in keys], [want[k] for k in keys], rtol=1e-12, atol=1e-12)
    # what the page shows is the results of the job it made, as the API keeps them
    (location,) = re.findall(r"content-location: (\S+)", answer.get_attribute("textContent"))
    kept = numbers(http.get(location).json())
    assert [kept[k] for k in keys] == [got[k] for k in keys]
    # and both are right: the example's target is its source turned 90° about z and moved by
    # (1, 2, 3) (by hand: x -> y, y -> -x)
    assert np.allclose(results["rotation"], [[0, -1, 0], [1, 0, 0], [0, 0, 1]], atol=1e-9)
    assert np.allclose(results["translation"], [1, 2, 3], atol=1e-9)
    assert browser_errors(browser) == []
