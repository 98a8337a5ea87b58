"""The workbench's sample data: a t-SNE of handwritten digits without writing code (the
sample picker fills the points, a click runs it), and the digits sample itself: the UCI
images as scikit-learn ships them, and accepted by every process it is offered for."""

from __future__ import annotations

import json
from typing import Any

import numpy as np
import pytest

from service.routes.ui import UI
from tests.browser.test_workbench import browser_errors, canvas, open_workbench, run, wait_until
from tests.live import LiveServer, execute, wait_for_status

pytestmark = pytest.mark.e2e

INDEX = json.loads((UI / "samples.json").read_text())["samples"]
DIGITS = json.loads((UI / "sample-digits.json").read_text())


def test_the_digits_are_the_uci_images_as_scikit_learn_reads_them() -> None:
    from sklearn.datasets import load_digits  # the peer's own reader of the same file

    images, digits = load_digits(return_X_y=True)
    points, labels = np.asarray(DIGITS["points"]), np.asarray(DIGITS["labels"])
    assert points.shape == (500, 64) and labels.shape == (500,)
    assert np.bincount(labels).tolist() == [50] * 10
    # each sample row is an image of that digit, in the file's order, and the first 50 of each
    rows = [int(np.flatnonzero((images == p).all(axis=1) & (digits == d))[0])
            for p, d in zip(points, labels, strict=True)]
    assert rows == sorted(rows)
    for d in range(10):
        assert [r for r, lab in zip(rows, labels, strict=True) if lab == d] == \
            np.flatnonzero(digits == d)[:50].tolist()
    assert "CC BY 4.0" in DIGITS["licence"] and "10.24432/C50P49" in DIGITS["source"]


def test_every_sample_names_processes_that_take_its_data(http: Any) -> None:
    for sample in INDEX:
        data = http.get(sample["file"]).json()  # served, as the page fetches it
        assert set(sample["fills"]) <= set(data), sample["id"]
        for process in sample["processes"]:
            described = http.get(f"/processes/{process}")
            assert described.status_code == 200, process
            assert sample["fills"][0] in described.json()["inputs"], process


@pytest.mark.parametrize("process", sorted({p for s in INDEX for p in s["processes"]}
                                          - {"embedding.tsne", "embedding.sne"}))
def test_each_process_offered_the_digits_runs_them(http: Any, process: str) -> None:
    """What the picker fills (the sample's members the process has as inputs) is accepted and
    runs to success with every other input at its default. t-SNE is the browser test's below;
    SNE takes the same inputs (and ~20 s here), so it is left to that."""
    (sample,) = [s for s in INDEX if process in s["processes"]]
    inputs = http.get(f"/processes/{process}").json()["inputs"]
    filled = {n: DIGITS[n] for n in sample["fills"] if n in inputs}
    assert "points" in filled
    response = execute(http, process, filled, prefer="respond-async")
    assert response.status_code == 201, response.text
    info = wait_for_status(http, response.json()["jobID"], timeout=120)
    assert info["status"] == "successful", http.get(f"/jobs/{info['jobID']}/results").text


def test_tsne_of_the_digits_sample(browser: Any, server: LiveServer, http: Any,
                                   shot: Any) -> None:
    from selenium.webdriver.support.ui import Select

    open_workbench(browser, server, "embedding.tsne")
    picker = browser.find_element("id", "sample")
    assert picker.is_displayed()
    Select(picker).select_by_value("digits")
    text = wait_until(browser, "const t = document.querySelector('#in-points');"
                      " return t.value.length > 1000 && t.value", 30)
    assert json.loads(text) == DIGITS["points"]
    info = browser.find_element("id", "sample-info").text
    assert "CC BY 4.0" in info and "UCI" in info
    job = run(browser, timeout=300)
    shot()
    sent = browser.execute_script("return window.workbench.state.sent.get(arguments[0])", job)
    assert set(sent) == {"points", "labels"}  # the options left at their defaults
    assert sent["labels"] == DIGITS["labels"]
    # coloured by digit: the legend has the ten digits, each in its own colour
    legend = browser.execute_script(
        "return Array.from(window.workbench.viewer.legend().entries())")
    assert sorted(label for label, _ in legend) == list(range(10))
    assert len({colour for _, colour in legend}) == 10
    drawn = browser.execute_script("""
      let n = 0; window.workbench.viewer.root.traverse((o) => {
        if (o.isPoints) n += o.geometry.attributes.position.count; });
      return n;""")
    assert drawn == 500
    assert canvas(browser)["n"] > 500  # 500 points at 8 px each, not a few dots
    # a t-SNE of digits keeps the classes apart: each image's nearest neighbour in the plane
    # is almost always the same digit (van der Maaten & Hinton 2008, fig. 2)
    embedding = np.asarray(http.get(f"/jobs/{job}/results/embedding").json(), dtype=float)
    assert embedding.shape == (500, 2)
    labels = np.asarray(DIGITS["labels"])
    d2 = ((embedding[:, None, :] - embedding[None, :, :]) ** 2).sum(-1)
    np.fill_diagonal(d2, np.inf)
    assert (labels[d2.argmin(axis=1)] == labels).mean() > 0.9
    assert browser_errors(browser) == []
