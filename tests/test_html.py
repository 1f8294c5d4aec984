"""The HTML page: self-contained, opens offline, shows the coloured mesh.

The page is opened in headless Chromium (Debian's ``chromium``; the tests skip
with a reason where it is absent; CI installs it).  Three checks:

* the page's screenshot shows the mesh in red and blue (with WebGL, and with
  the 2D-canvas fallback forced by ``#canvas2d``);
* the viewer script ran (it marks ``#status`` ready in the DOM);
* **no network requests**: Chromium's net log records every URL request
  with its initiator.  Requests a page makes carry the page's origin
  (``null`` for a file:// page); Chromium's own background requests (update
  and time checks that the flags do not all silence) carry "not an origin".
  The log must hold no request initiated by the page.  A control page with
  one image and one fetch from elsewhere shows that such requests are
  recorded.  DNS is mapped to nothing, so no request reaches the network.
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess

import numpy as np
import pytest

from conftest import OVERFLOW_CHECK
from dentopo import ariaDNE, render_curvature, render_panel

Image = pytest.importorskip("PIL.Image", reason="Pillow is needed to read screenshots")
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
pytestmark = pytest.mark.skipif(
    CHROMIUM is None, reason="headless Chromium (Debian package 'chromium') is not installed"
)


def chromium(tmp_path, url: str, *args: str) -> subprocess.CompletedProcess:
    profile = tmp_path / f"profile{len(list(tmp_path.glob('profile*')))}"
    command = [
        CHROMIUM,
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--no-first-run",
        "--host-resolver-rules=MAP * ~NOTFOUND",
        f"--user-data-dir={profile}",
        *args,
        url,
    ]
    return subprocess.run(command, capture_output=True, text=True, timeout=120, check=True)


def page_requests(net_log) -> list[str]:
    """URLs of the requests a page initiated, from a Chromium net log."""
    log = json.loads(net_log.read_text())
    start_job = log["constants"]["logEventTypes"]["URL_REQUEST_START_JOB"]
    return [
        event["params"]["url"]
        for event in log["events"]
        if event["type"] == start_job
        and "url" in event.get("params", {})
        and event["params"].get("initiator") != "not an origin"
    ]


def screenshot(tmp_path, url: str, name: str) -> np.ndarray:
    path = tmp_path / name
    chromium(tmp_path, url, "--window-size=800,600", f"--screenshot={path}")
    with Image.open(path) as png:
        return np.asarray(png.convert("RGB")).astype(int)


@pytest.fixture(scope="module")
def tooth_page(tmp_path_factory):
    from dentopo.samples import tooth

    mesh = tooth(rings=16)
    path = tmp_path_factory.mktemp("html") / "tooth.html"
    render_curvature(mesh, ariaDNE(mesh), view="top", html=path)
    return path


@pytest.mark.parametrize("mode", ["", "#canvas2d"])
def test_page_shows_the_coloured_mesh(tmp_path, tooth_page, mode):
    image = screenshot(tmp_path, tooth_page.as_uri() + mode, "page.png")
    mesh = image[40:480]  # between the caption and the colour bar
    red = (mesh[..., 0] - mesh[..., 2] > 40).sum()
    blue = (mesh[..., 2] - mesh[..., 0] > 40).sum()
    assert red > 2000 and blue > 300, (red, blue)


def test_viewer_ran(tmp_path, tooth_page):
    dom = chromium(tmp_path, tooth_page.as_uri(), "--dump-dom").stdout
    status = re.search(r'<div id="status"[^>]*>', dom).group(0)
    assert 'data-ready="yes"' in status
    assert re.search(r'data-renderer="(webgl2|webgl|canvas2d)"', status)


def test_page_makes_no_network_requests(tmp_path, tooth_page):
    net_log = tmp_path / "net.json"
    chromium(tmp_path, tooth_page.as_uri(), f"--log-net-log={net_log}", "--dump-dom")
    assert page_requests(net_log) == []


def test_the_request_check_sees_requests(tmp_path):
    control = tmp_path / "control.html"
    control.write_text(
        '<!DOCTYPE html><img src="http://dentopo-control.invalid/a.png">'
        '<script>fetch("https://dentopo-control.invalid/b").catch(() => 0)</script>'
    )
    net_log = tmp_path / "net.json"
    chromium(tmp_path, control.as_uri(), f"--log-net-log={net_log}", "--dump-dom")
    assert sorted(page_requests(net_log)) == [
        "http://dentopo-control.invalid/a.png",
        "https://dentopo-control.invalid/b",
    ]


def test_page_is_self_contained(tooth_page):
    text = tooth_page.read_text()
    assert "default-src 'none'" in text  # the browser refuses any request
    code = re.sub(r'<script type="application/json"[^>]*>.*?</script>', "", text, flags=re.S)
    assert not re.search(r"(https?:|//[a-z]|src=|href=|@import|url\()", code, flags=re.I)


def test_panel_page_has_one_canvas_per_mesh(tmp_path, tooth):
    path = tmp_path / "panel.html"
    result = ariaDNE(tooth)
    render_panel([(tooth, result)] * 3, labels=["a", "b", "c"], html=path, limits=0.3)
    dom = chromium(tmp_path, path.as_uri(), "--dump-dom").stdout
    assert dom.count("<canvas") == 3
    assert "±0.3 (fixed)" in dom


# ---------------------------------------------------------------------------
# captions stay inside their boxes, at any window size


@pytest.mark.parametrize("size", ["480,480", "1400,900"])
def test_captions_do_not_overflow(tmp_path, tooth, size):
    page = tmp_path / "panel.html"
    result = ariaDNE(tooth)
    labels = [
        "a_very_long_specimen_name_without_spaces_from_a_museum_catalogue.ply",
        "b.ply",
        "a label with several words that needs to wrap",
        "d",
    ]
    render_panel([(tooth, result)] * 4, labels=labels, html=page)
    checked = tmp_path / "checked.html"
    checked.write_text(page.read_text().replace("</body>", OVERFLOW_CHECK + "</body>"))
    dom = chromium(tmp_path, checked.as_uri(), f"--window-size={size}", "--dump-dom").stdout
    assert 'data-checked="4"' in dom  # the check ran, over the four captions
    overflow = re.search(r"data-overflow=\"([^\"]*)\"", dom).group(1)
    assert overflow == "[]", overflow


def test_page_keeps_its_provenance(tmp_path, tooth):
    from dentopo.figures import camera_for, read_provenance

    page = tmp_path / "tooth.html"
    result = ariaDNE(tooth)
    render_curvature(tooth, result, html=page, limits=0.2, azimuth=15.0)
    record = read_provenance(page)
    assert record["metric"] == "local_curvature"
    assert record["parameters"]["limits"] == [-0.2, 0.2]
    assert record["parameters"]["bandwidth"] == result.bandwidth
    assert record["input"] == {"file": None, "sha256": None}
    camera = camera_for(result.mesh.vertices, result.mesh.faces, azimuth=15.0)
    np.testing.assert_allclose(record["camera"]["position"], camera.position)
    assert '<script type="application/json" id="dentopo-provenance">' in page.read_text()
