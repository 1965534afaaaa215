"""The run report: one self-contained HTML page per run, built from the files of the output
folder, opened in a real headless browser (Chromium from the distribution, Selenium)."""

from __future__ import annotations

import json
import os
import re
import shutil
import sys
from html.parser import HTMLParser
from pathlib import Path

import pytest

from fretbem.app import cli
from fretbem.output.report import build_report

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[3]
CHROMIUM, CHROMEDRIVER = Path("/usr/bin/chromium"), Path("/usr/bin/chromedriver")
SCREENSHOT = ROOT / "docs" / "how-to" / "report_screenshot.png"


def _rig_scene(tmp_path: Path) -> Path:
    """The rig example at 31 pairs with a small stress line and a quick fatigue map."""
    text = (ROOT / "examples" / "fretting_rig.toml").read_text()
    data = tomllib.loads(text)
    assert data["stress"]["line"][0]["x"] == "trailing-edge"
    text = text.replace("pairs = 61", "pairs = 31").replace("n = 40", "n = 8")
    text = text.replace(
        'methods = ["swt", "mwcm"]', 'methods = ["swt", "mwcm"]\nmap_points = [11, 5]'
    )
    path = tmp_path / "rig.toml"
    path.write_text(text)
    return path


@pytest.fixture(scope="module")
def rig_out(tmp_path_factory):
    """`fretbem run rig.toml --report` (stresses, fatigue, figures; no VTK)."""
    tmp = tmp_path_factory.mktemp("report")
    out = tmp / "rig-out"
    code = cli.main(["run", str(_rig_scene(tmp)), "--no-vtk", "--report", "--out", str(out)])
    assert code == 0
    return out


class _Page(HTMLParser):
    """Section ids, images and the text of the page; checks that every tag closes."""

    VOID = frozenset({"meta", "img", "br", "hr", "link", "input"})

    def __init__(self):
        super().__init__()
        self.sections, self.images, self.scripts, self.text, self.stack = [], [], 0, [], []

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        if tag == "section":
            self.sections.append(attrs["id"])
        if tag == "img":
            self.images.append(attrs)
        if tag == "script" or tag == "link":
            self.scripts += 1
        if tag not in self.VOID:
            self.stack.append(tag)

    def handle_endtag(self, tag):
        assert self.stack.pop() == tag, tag

    def handle_data(self, data):
        self.text.append(data)


def _page(markup: str) -> _Page:
    page = _Page()
    page.feed(markup)
    assert not page.stack
    return page


def test_report_holds_the_run(rig_out):
    summary = json.loads((rig_out / "summary.json").read_text())
    markup = (rig_out / "report.html").read_text()
    page = _page(markup)
    text = " ".join(page.text)
    assert page.sections == ["scene", "zones", "checks", "errors", "timings", "stress",
                             "fatigue", "loops", "figures", "files"]  # fmt: skip
    loops = (rig_out / "loops.csv").read_text().splitlines()
    assert f"loops.csv: {len(loops) - 1} rows" in " ".join(page.text)
    assert page.scripts == 0  # self-contained: no script, no external file
    assert not re.search(r"(src|href)=\"(?!data:|#)", markup)
    hertz = summary["hertz"]
    assert f"{hertz['a']:.4f} mm" in text and f"{hertz['p0']:.2f} MPa" in text
    for step in summary["steps"]:
        low, high = step["theory_stick_zone"]
        assert f"[{low:+.4f}, {high:+.4f}]" in text
        assert f"{100 * step['e_q_max']:.3f} / {100 * step['est_q_max']:.3f}" in text
    assert "all result checks passed" in text
    fatigue = json.loads((rig_out / "fatigue.json").read_text())
    swt = fatigue["methods"]["swt"]
    assert f"{swt['hot_spot']['x_mm']:.4g}" in text
    assert f"{swt['parameter_at_hot_spot']:.4g}" in text
    pngs = sorted(p.name for p in rig_out.glob("*.png"))
    assert sorted(i["alt"] for i in page.images) == pngs
    assert all(i["src"].startswith("data:image/png;base64,") for i in page.images)


def test_report_reads_whatever_result_files_exist(rig_out, tmp_path):
    # summary.json alone: the run's sections, none of the optional ones
    bare = tmp_path / "bare"
    bare.mkdir()
    shutil.copy(rig_out / "summary.json", bare)
    assert _page(build_report(bare)).sections == ["scene", "zones", "checks", "errors",
                                                  "timings", "files"]  # fmt: skip
    # loops and wear files of other writers appear as their own sections
    (bare / "loops.csv").write_text("step,x,Q,delta\nB,0.0,45.0,0.001\nD,0.0,-45.0,-0.001\n")
    (bare / "wear_summary.csv").write_text(
        "N,energy,max_depth_pad\n"
        + "".join(f"{k * 1000},{k * 0.1},{k * 1e-5}\n" for k in range(40))
    )
    (bare / "wear.json").write_text(json.dumps({"law": "archard", "cycles": 40000}))
    page = _page(build_report(bare))
    assert "loops" in page.sections and "wear" in page.sections
    text = " ".join(page.text)
    assert "loops.csv: 2 rows" in text and "wear_summary.csv: 40 rows" in text
    assert "... 28 rows not shown ..." in text and "archard" in text
    # a broken extra file is named, not a crash
    (bare / "slip.csv").write_bytes(b"\xff\xfe\x00bad")
    assert "slip.csv" in " ".join(_page(build_report(bare)).text)


def test_report_command(rig_out, tmp_path, capsys):
    out = tmp_path / "again"
    shutil.copytree(rig_out, out)
    marker = json.loads((out / ".fretbem-output").read_text())
    marker["directory"] = str(out.resolve())
    (out / ".fretbem-output").write_text(json.dumps(marker))
    (out / "report.html").unlink()
    marker["files"].remove("report.html")
    (out / ".fretbem-output").write_text(json.dumps(marker))
    assert cli.main(["report", str(out)]) == 0
    assert "report.html" in capsys.readouterr().out
    assert (out / "report.html").stat().st_size > 100_000
    # the page is listed in the marker: the next run replaces the folder without --overwrite
    assert "report.html" in json.loads((out / ".fretbem-output").read_text())["files"]
    assert cli.main(["demo", "--pairs", "21", "--no-figures", "--no-vtk", "--out", str(out)]) == 0
    # a folder fretbem did not write, or one without summary.json: exit 2, one line
    (tmp_path / "mine").mkdir()
    (tmp_path / "mine" / "notes.txt").write_text("x")
    assert cli.main(["report", str(tmp_path / "mine")]) == 2
    err = capsys.readouterr().err
    assert "no readable summary.json" in err and err.count("\n") == 1


def _browser():
    """Headless Chromium through Selenium; None where it is not installed (outside CI)."""
    if not (CHROMIUM.exists() and CHROMEDRIVER.exists()):
        if os.environ.get("CI"):
            pytest.fail("CI must install chromium and chromium-driver (.ci/run does)")
        pytest.skip("chromium and chromium-driver are not installed (apt-get install them)")
    if not os.environ.get("CI"):
        pytest.importorskip("selenium", reason="selenium is not installed (pip install selenium)")
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = str(CHROMIUM)
    for argument in ("--headless=new", "--no-sandbox", "--disable-gpu",
                     "--disable-dev-shm-usage", "--window-size=1200,1600"):  # fmt: skip
        options.add_argument(argument)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    return webdriver.Chrome(service=Service(str(CHROMEDRIVER)), options=options)


def test_report_in_a_real_browser(rig_out, tmp_path):
    browser = _browser()
    try:
        browser.get((rig_out / "report.html").resolve().as_uri())
        assert browser.title.startswith("fretbem run report: nurbs, 31 pairs, steps A..E")
        errors = [e for e in browser.get_log("browser") if e["level"] in ("SEVERE", "ERROR")]
        assert errors == []
        images = browser.execute_script(
            "return Array.from(document.images).map(i => [i.alt, i.complete, i.naturalWidth])"
        )
        assert len(images) == len(list(rig_out.glob("*.png"))) >= 5
        assert all(done and width > 0 for _, done, width in images), images
        height = browser.execute_script("return document.body.scrollHeight")
        browser.set_window_size(1200, min(height + 50, 3000))
        shot = tmp_path / "report.png"
        assert browser.save_screenshot(str(shot))
    finally:
        browser.quit()
    assert shot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and shot.stat().st_size > 50_000
    if not SCREENSHOT.exists() or os.environ.get("FRETBEM_UPDATE_SCREENSHOT"):
        shutil.copy(shot, SCREENSHOT)  # the docs page shows it


def test_ci_installs_the_browser_and_runs_the_readme_command():
    script = (ROOT / ".ci" / "run").read_text().splitlines()
    readme = (ROOT / "README.md").read_text()
    command = 'python -m pip install -e ".[test,docs]" && python -m pytest'
    assert command in readme and script[-1] == command
    install = next(k for k, line in enumerate(script) if "apt-get install" in line)
    assert "chromium chromium-driver" in script[install]
    assert install < script.index(command) and any(
        line.startswith('export CI="${CI:-1}"') for line in script
    )
