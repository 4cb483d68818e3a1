"""Run and study reports (issue 15): `clearance run` writes report.html next to the results,
`clearance report` rebuilds it from the file, studies get one with a viewer per case; the
pages are opened in headless Chromium (tests/browser.py)."""

from __future__ import annotations

import re
import shutil

import netCDF4
import numpy as np
import pytest
from browser import chrome, severe_logs, wait_for
from selenium.webdriver.common.by import By
from typer.testing import CliRunner

import clearance
from clearance.cli.main import app
from clearance.pipeline import run_scenario
from clearance.scenario import default_scenario_path, load_scenario, with_overrides
from clearance.sweep import loads_study, run_study


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """The default scenario cut to 0.1 s, with its figures, as `clearance run` writes it."""
    out = tmp_path_factory.mktemp("report")
    s = with_overrides(
        load_scenario(default_scenario_path("ups_upu")), {"trajectory.duration": 0.1}
    )
    o = run_scenario(s, out_dir=out, log=None, figures=True)
    return o, out


@pytest.fixture(scope="module")
def browser():
    d = chrome()
    d.set_window_size(1280, 1600)
    yield d
    d.quit()


def _cells(driver, table: int) -> list[list[str]]:
    rows = driver.find_elements(By.CSS_SELECTOR, f"table:nth-of-type({table}) tbody tr")
    return [[td.text for td in r.find_elements(By.TAG_NAME, "td")] for r in rows]


def test_run_writes_a_report_that_shows_the_run(run, browser):
    """report.html is among the files; in the browser its joint table shows the run's
    summary, every figure is embedded, the viewer in it is drawn without errors, and the
    scenario and version are there."""
    o, out = run
    page = out / "report.html"
    assert page in o.files and page.is_file()
    figures = sorted((out / "figures").glob("*.png"))
    assert len(figures) >= 5
    text = page.read_text()
    assert text.count("data:image/png;base64,") == len(figures)
    assert f"clearance {clearance.__version__}" in text
    browser.get(page.as_uri())
    joints = {r[0]: r for r in _cells(browser, 1)}
    for name, j in o.summary["joints"].items():
        assert joints[name][1] == f"{j['peak_contact_force']:.1f}"
        assert joints[name][4] == str(j["impacts"])
    status = browser.find_element(By.XPATH, "//td[text()='clearance']/following-sibling::td")
    assert status.text.startswith("ok")
    browser.switch_to.frame(browser.find_element(By.CSS_SELECTOR, "iframe.viewer"))
    wait_for(browser, "window.viewer && window.viewer.ready && window.viewer.renders > 0")
    assert browser.execute_script("return window.viewer.errors") == []
    assert browser.execute_script("return window.viewer.runs") == ["ideal", "clearance"]
    browser.switch_to.default_content()
    assert "[clearance.joints.S_1]" in browser.find_element(By.TAG_NAME, "pre").get_attribute(
        "textContent"
    )
    assert severe_logs(browser) == []


def test_report_rebuilds_from_the_file_alone(run, tmp_path, browser):
    """A copy of the result file alone: `clearance report` draws the missing figures and,
    for a file without the summary attribute (older files), takes the joint table from the
    file's peaks and event log, which agree with the run's summary."""
    o, out = run
    nc = tmp_path / "ups_upu.nc"
    shutil.copy(out / "ups_upu.nc", nc)
    with netCDF4.Dataset(nc, "a") as d:
        d.delncattr("summary")
    r = CliRunner().invoke(app, ["report", str(nc)])
    assert r.exit_code == 0, r.output
    page = tmp_path / "report.html"
    assert page.is_file() and len(list((tmp_path / "figures").glob("*.png"))) >= 5
    browser.get(page.as_uri())
    joints = {r[0]: r for r in _cells(browser, 1)}
    for name, j in o.summary["joints"].items():
        assert joints[name][1] == f"{j['peak_contact_force']:.1f}"
        assert joints[name][4] == str(j["impacts"])
        assert float(joints[name][5]) == pytest.approx(j["max_penetration"] * 1e6, rel=1e-3)
    assert severe_logs(browser) == []
    bad = CliRunner().invoke(app, ["report", str(tmp_path / "none.nc")])
    assert bad.exit_code == 2 and "none.nc" in bad.output


def test_study_report_links_a_viewer_per_case(tmp_path, browser):
    folder = tmp_path / "study"
    text = f"""format_version = 1
[study]
name = "r"
base = "ups_upu"
folder = "{folder}"
metrics = ["peak_contact_force", "impacts"]
[set]
trajectory.duration = 0.03
solver.dt_out = 1e-3
[[parameter]]
name = "radial_clearance"
path = ["clearance.joints.S_1.radial_clearance", "clearance.joints.S_3.radial_clearance"]
values = [1e-4, 3e-4]
"""
    rep = run_study(loads_study(text, source="r.toml"), scheduler="serial", progress=False)
    assert rep.complete
    assert not list((folder / "cases").glob("report.html"))  # no report per case
    r = CliRunner().invoke(app, ["report", str(folder)])
    assert r.exit_code == 0, r.output
    page = folder / "report.html"
    browser.get(page.as_uri())
    rows = browser.find_elements(By.CSS_SELECTOR, "table tbody tr")
    assert len(rows) == 2
    links = [a.get_attribute("href") for a in browser.find_elements(By.LINK_TEXT, "viewer")]
    assert len(links) == 2
    values = sorted(
        float(re.sub(r"[^0-9.e-]", "", row.find_elements(By.TAG_NAME, "td")[3].text))
        for row in rows
    )
    assert np.allclose(values, [1e-4, 3e-4])
    assert len(browser.find_elements(By.CSS_SELECTOR, ".figs img")) >= 1  # summary plots
    browser.get(links[1])
    wait_for(browser, "window.viewer && window.viewer.ready && window.viewer.renders > 0")
    assert browser.execute_script("return window.viewer.errors") == []
    assert severe_logs(browser) == []
