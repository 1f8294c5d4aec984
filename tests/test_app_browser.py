"""The page of ``dentopo app`` in a real browser (headless Chromium through Selenium).

One app is started on a folder of the package's samples (one in a subfolder), a
corrupt file and a file whose name is HTML, and one browser visits it; the tests
run in order on that one page: the meshes are listed (names as text), the crop
slider recolours the 3D view without asking the server, a batch runs and its
rows are the table the app wrote, and the page's CSV link gives that table.

Screenshots go to a temporary folder, or to ``$DENTOPO_APP_SCREENSHOTS``.
Skipped when Chromium or its driver is missing.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
import re
import shutil
from pathlib import Path

import pytest

from app_server import start
from dentopo.samples import sample_paths

CHROMEDRIVER = "/usr/bin/chromedriver"
CHROMIUM = "/usr/bin/chromium"
#: A name that HTML would turn into a <b> element and an "&" ("/" cannot be in a file name).
HTML_NAME = "<b>x&amp;y.ply"
REMOVED = "#d62728"

pytestmark = pytest.mark.slow

webdriver = pytest.importorskip("selenium.webdriver", reason="selenium is not installed")
from selenium.common.exceptions import TimeoutException  # noqa: E402
from selenium.webdriver.chrome.service import Service  # noqa: E402
from selenium.webdriver.common.by import By  # noqa: E402
from selenium.webdriver.support.ui import WebDriverWait  # noqa: E402


def _missing_browser() -> str | None:
    for path, package in ((CHROMEDRIVER, "chromium-driver"), (CHROMIUM, "chromium")):
        if not os.path.exists(path):
            return f"{path} not found (Debian package {package})"
    return None


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    """The samples (sphere in a subfolder), a corrupt PLY and a sample named as HTML."""
    root = tmp_path_factory.mktemp("app-folder")
    paths = sample_paths()
    shutil.copy(paths["tooth"], root / "tooth.ply")
    shutil.copy(paths["saddle"], root / "saddle.ply")
    (root / "sub").mkdir()
    shutil.copy(paths["sphere"], root / "sub" / "sphere.ply")
    (root / "bad.ply").write_bytes(b"ply\nthis is not a mesh \x00\xff garbage\n")
    shutil.copy(paths["tooth"], root / HTML_NAME)
    return root


#: The folder's meshes as the app names them (relative, with "/").
EXPECTED = {"tooth.ply", "saddle.ply", "sub/sphere.ply", "bad.ply", HTML_NAME}
READABLE = EXPECTED - {"bad.ply"}


@pytest.fixture(scope="module")
def server(folder):
    """``dentopo app FOLDER --no-browser --port 0`` as a subprocess; yields its URL."""
    reason = _missing_browser()
    if reason:
        pytest.skip(reason)
    running = start(folder)  # not waited for: the page shows the meshes being read
    try:
        yield running.url
    finally:
        running.stop()


@pytest.fixture(scope="module")
def shots(tmp_path_factory):
    wanted = os.environ.get("DENTOPO_APP_SCREENSHOTS")
    if wanted:
        Path(wanted).mkdir(parents=True, exist_ok=True)
        return Path(wanted)
    return tmp_path_factory.mktemp("app-screenshots")


@pytest.fixture(scope="module")
def page(server, tmp_path_factory):
    """A headless Chromium on the app's page, once its first state is drawn."""
    options = webdriver.ChromeOptions()
    for argument in (
        "--headless=new",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-dev-shm-usage",
        "--disable-background-networking",
        "--disable-component-update",
        "--no-first-run",
        "--disable-sync",
        "--enable-unsafe-swiftshader",  # WebGL (plotly's mesh3d) on the software renderer
        "--window-size=1300,1000",
        f"--user-data-dir={tmp_path_factory.mktemp('chromium-profile')}",
    ):
        options.add_argument(argument)
    options.binary_location = CHROMIUM
    driver = webdriver.Chrome(service=Service(executable_path=CHROMEDRIVER), options=options)
    try:
        driver.set_script_timeout(60)
        driver.get(server)
        wait(driver, 60, "the first state drawn", lambda d: status(d, "ready"))
        yield driver
    finally:
        driver.quit()


def wait(driver, seconds, what, condition):
    try:
        return WebDriverWait(driver, seconds, poll_frequency=0.25).until(condition)
    except TimeoutException:
        errors = status(driver, "errors")
        message = driver.execute_script(
            "const m = document.getElementById('message'); return m.hidden ? '' : m.textContent"
        )
        pytest.fail(f"waited {seconds} s for {what}; page errors: {errors!r}; message: {message!r}")


def status(driver, name):
    return driver.execute_script(
        "return document.getElementById('app-status').dataset[arguments[0]] || ''", name
    )


def page_too_wide(driver):
    """Whether the page needs a horizontal scroll bar (something wider than the window)."""
    return driver.execute_script(
        "const root = document.documentElement; return root.scrollWidth > root.clientWidth + 1"
    )


def click(driver, element):
    driver.execute_script("arguments[0].scrollIntoView({block: 'center'})", element)
    element.click()


def card(driver, path):
    for element in driver.find_elements(By.CSS_SELECTOR, "#meshes .card"):
        if element.get_attribute("data-path") == path:
            return element
    return None


def fetch_text(driver, url):
    """`url` fetched by the page itself (its cookie, its origin): (status, text)."""
    return driver.execute_async_script(
        """
        const done = arguments[arguments.length - 1];
        fetch(arguments[0], {credentials: "same-origin"})
          .then(async (r) => done([r.status, await r.text()]))
          .catch((e) => done([0, String(e)]));
        """,
        url,
    )


def test_page_lists_the_meshes_names_as_text(page, shots):
    wait(
        page,
        60,
        "a card for every mesh",
        lambda d: (
            {c.get_attribute("data-path") for c in d.find_elements(By.CSS_SELECTOR, ".card")}
            >= EXPECTED
        ),
    )
    paths = [c.get_attribute("data-path") for c in page.find_elements(By.CSS_SELECTOR, ".card")]
    assert sorted(paths) == sorted(EXPECTED)

    # the corrupt file's card says why, in the error style
    wait(
        page,
        60,
        "the bad file's error",
        lambda d: card(d, "bad.ply").find_elements(By.CSS_SELECTOR, ".error"),
    )
    error = card(page, "bad.ply").find_element(By.CSS_SELECTOR, ".error").text
    assert error.strip()
    for path in READABLE:
        assert not card(page, path).find_elements(By.CSS_SELECTOR, ".error"), path

    # the HTML name is text: no <b> element anywhere in the meshes, the name shown as written
    html_card = card(page, HTML_NAME)
    assert html_card.find_element(By.CSS_SELECTOR, ".name").text == HTML_NAME
    assert page.execute_script("return document.querySelectorAll('#meshes b').length") == 0
    assert page.execute_script("return document.querySelectorAll('main b').length") == 0
    # the groups: a heading for the subfolder
    headings = [h.text for h in page.find_elements(By.CSS_SELECTOR, "#meshes .group-title")]
    assert "sub" in headings
    page.save_screenshot(str(shots / "1-meshes.png"))
    assert status(page, "errors") == ""


def vertex_colors(driver):
    return driver.execute_script(
        "const v = document.getElementById('view');"
        "return v.data && v.data[0] && v.data[0].vertexcolor ? Array.from(v.data[0].vertexcolor)"
        " : null"
    )


def camera_eye(driver):
    return driver.execute_script(
        "const v = document.getElementById('view');"
        "const c = v.layout && v.layout.scene && v.layout.scene.camera;"
        "return c && c.eye ? [c.eye.x, c.eye.y, c.eye.z] : null"
    )


def test_crop_slider_recolours_the_view(page, shots):
    click(page, card(page, "tooth.ply"))
    wait(page, 90, "the oriented crown in the view", lambda d: vertex_colors(d))
    before = vertex_colors(page)
    assert REMOVED not in before  # no crop yet: every vertex in the tooth colour
    share_before = page.find_element(By.ID, "crop-share").text
    assert share_before.startswith("0.0%")
    found_up = page.find_element(By.ID, "found-up").text
    assert len(found_up.split(",")) == 3
    assert "file\u2019s coordinates" in page.find_element(By.ID, "found-up-note").text
    # the oriented view opens seen from above
    eye = camera_eye(page)
    assert eye is not None and eye[2] == pytest.approx(1.8)
    assert page.find_element(By.ID, "camera-occlusal").get_attribute("aria-pressed") == "true"

    slider = page.find_element(By.ID, "crop")
    top = float(slider.get_attribute("max"))
    assert top > 0
    previews = (
        "return performance.getEntriesByType('resource')"
        ".filter(e => e.name.includes('/api/preview')).length"
    )
    page.execute_script("performance.setResourceTimingBufferSize(100000)")
    previews_before = page.execute_script(previews)
    assert previews_before >= 1
    page.execute_script(
        "const s = document.getElementById('crop');"
        "s.value = String(Number(s.max) * 0.3);"
        "s.dispatchEvent(new Event('input', {bubbles: true}));"
    )
    wait(
        page,
        10,
        "the removed share",
        lambda d: d.find_element(By.ID, "crop-share").text != share_before,
    )
    wait(page, 10, "the colours", lambda d: vertex_colors(d) != before)
    after = vertex_colors(page)
    assert len(after) == len(before)
    removed = after.count(REMOVED)
    assert 0 < removed < len(after)
    share = float(page.find_element(By.ID, "crop-share").text.split("%")[0])
    assert share == pytest.approx(100 * removed / len(after), abs=0.06)
    # the slider is the page's own: moving it asked the server nothing
    assert page.execute_script(previews) == previews_before
    # the first crop turned the view to the side (the crop can be seen), without a redraw
    wait(page, 10, "the side camera", lambda d: camera_eye(d)[2] != pytest.approx(1.8))
    assert camera_eye(page)[2] == pytest.approx(0.7)
    assert page.find_element(By.ID, "camera-side").get_attribute("aria-pressed") == "true"
    assert vertex_colors(page) == after  # the same trace, only turned
    page.save_screenshot(str(shots / "2-crop.png"))
    # the reader may turn it back; a second crop does not turn it again
    click(page, page.find_element(By.ID, "camera-occlusal"))
    wait(page, 10, "the occlusal camera again", lambda d: camera_eye(d)[2] == pytest.approx(1.8))
    page.execute_script(
        "const s = document.getElementById('crop');"
        "s.value = String(Number(s.max) * 0.35);"
        "s.dispatchEvent(new Event('input', {bubbles: true}));"
    )
    wait(page, 10, "the new colours", lambda d: vertex_colors(d) != after)
    assert camera_eye(page)[2] == pytest.approx(1.8)

    # back to no crop: everything in the tooth colour again
    page.execute_script(
        "const s = document.getElementById('crop'); s.value = '0';"
        "s.dispatchEvent(new Event('input', {bubbles: true}));"
    )
    wait(page, 10, "the colours without a crop", lambda d: REMOVED not in vertex_colors(d))
    assert status(page, "errors") == ""


def api(driver, method, path, body=None):
    """The page's own request (its secret header), answered as JSON."""
    return driver.execute_async_script(
        "const [method, path, body, done] = arguments;"
        "const token = document.querySelector('meta[name=dentopo-token]').content;"
        "fetch(path, {method, headers: {'Content-Type': 'application/json',"
        " 'X-Dentopo-Token': token}, body: body === null ? undefined : JSON.stringify(body)})"
        ".then(r => r.json()).then(done, e => done({error: String(e)}));",
        method,
        path,
        body,
    )


def test_apply_to_all_as_a_share_of_the_height_saves_a_fraction(page):
    page.execute_script(
        "const s = document.getElementById('crop');"
        "s.value = String(Number(s.max) * 0.25);"
        "s.dispatchEvent(new Event('input', {bubbles: true}));"
    )
    box = page.find_element(By.ID, "crop-as-share")
    if not box.is_selected():
        click(page, box)
    assert "25%" in page.find_element(By.ID, "crop-value").text
    click(page, page.find_element(By.ID, "apply-all"))

    def saved(driver):
        protocol = api(driver, "GET", "/api/state")["protocol"]
        return protocol if protocol and protocol.get("crop_fraction") else None

    protocol = wait(page, 30, "the folder's protocol", saved)
    assert protocol["crop_fraction"] == pytest.approx(0.75, abs=0.005)
    assert protocol["crop_below"] is None  # each crown cropped at its own height
    # applying ticked "prepare before measuring" (the server keeps it), and the line above Run
    # says what a run will do: the folder's protocol, by name, for every readable mesh
    wait(
        page, 10, "the box ticked", lambda d: d.find_element(By.ID, "prepare-before").is_selected()
    )
    assert api(page, "GET", "/api/state")["prepare"] is True
    plan = page.find_element(By.ID, "run-plan").text
    name = protocol["name"]
    meshes = api(page, "GET", "/api/state")["meshes"]
    folder_count = sum(1 for m in meshes if m["protocol"] == "folder")
    assert folder_count == len(EXPECTED)
    assert plan.startswith("Each mesh is prepared with its protocol first:"), plan
    assert f"the folder\u2019s ({name}) for {folder_count}" in plan, plan
    click(page, page.find_element(By.ID, "prepare-before"))  # unticked: as read
    assert page.find_element(By.ID, "run-plan").text == "Meshes are measured as read."
    api(page, "POST", "/api/protocol", {"scope": "all", "protocol": None, "prepare": False})
    state = api(page, "GET", "/api/state")
    assert state["protocol"] is None and state["prepare"] is False
    click(page, box)  # unticked again
    assert status(page, "errors") == ""


def _number(text):
    try:
        return float(text)
    except ValueError:
        return None


def relative(name, folder):
    """A table's file name as the app names the mesh (relative to the folder, with "/")."""
    name = name.replace("\\", "/")
    if os.path.isabs(name):
        name = Path(os.path.relpath(name, folder)).as_posix()
    return name[2:] if name.startswith("./") else name


def test_batch_rows_are_the_table_written(page, shots, folder):
    # ariaDNE and slope (the sphere and the saddle get an orientation warning), one job, as read
    page.execute_script(
        "for (const box of document.querySelectorAll('#metrics input'))"
        "  box.checked = box.value === 'ariadne' || box.value === 'slope';"
        "document.getElementById('jobs').value = '1';"
        "document.getElementById('prepare-before').checked = false;"
    )
    assert sorted(
        page.execute_script(
            "return Array.from(document.querySelectorAll('#metrics input:checked'), b => b.value)"
        )
    ) == ["ariadne", "slope"]
    click(page, page.find_element(By.ID, "run"))
    wait(
        page,
        240,
        "the run to end",
        lambda d: (
            d.find_element(By.ID, "progress").get_attribute("data-state")
            in ("done", "failed", "cancelled")
        ),
    )
    state = page.find_element(By.ID, "progress").get_attribute("data-state")
    log = page.execute_script("return document.getElementById('log').textContent")
    assert state == "done", log
    progress = page.find_element(By.ID, "progress").text
    done, total = (int(x) for x in progress.split("/"))
    assert done == total and total in (len(READABLE), len(EXPECTED)), progress

    code, text = fetch_text(page, "/api/state")
    assert code == 200
    table = Path(json.loads(text)["table"])
    assert table.name == "results.csv"
    with table.open(newline="", encoding="utf-8") as handle:
        written = list(csv.DictReader(handle))
    for row in written:
        row["file"] = relative(row["file"], folder)
    files = [row["file"] for row in written]
    assert set(files) >= READABLE
    assert set(files) <= EXPECTED
    assert len(files) == len(set(files))

    wait(
        page,
        30,
        "one table row per row written",
        lambda d: len(d.find_elements(By.CSS_SELECTOR, "#results tbody tr")) == len(written),
    )
    header = page.execute_script(
        "return Array.from(document.querySelectorAll('#results thead th'), th => th.dataset.column)"
    )
    assert header[0] == "file"
    assert set(header) <= set(written[0]), "a column the table file does not have"
    shown = page.execute_script(
        """
        const header = Array.from(document.querySelectorAll('#results thead th'),
                                  (th) => th.dataset.column);
        return Array.from(document.querySelectorAll('#results tbody tr'), (tr) => {
          const row = {};
          Array.from(tr.cells).forEach((td, i) => { row[header[i]] = td.dataset.v; });
          return row;
        });
        """
    )
    by_file = {row["file"]: row for row in written}
    assert sorted(relative(row["file"], folder) for row in shown) == sorted(by_file)
    for row in shown:
        expected = by_file[relative(row["file"], folder)]
        for column in header:
            if column == "file":
                continue
            a, b = row[column], expected[column]
            x, y = _number(a), _number(b)
            if x is not None and y is not None:
                assert math.isclose(x, y, rel_tol=1e-9, abs_tol=1e-12) or (
                    math.isnan(x) and math.isnan(y)
                ), (row["file"], column, a, b)
            else:
                # the CSV puts an apostrophe before a text a spreadsheet would run ("'+z")
                b = b[1:] if b and b.startswith("'") else b
                assert (a or "") == (b or ""), (row["file"], column, a, b)
    # the file names in the table are text too
    assert page.execute_script("return document.querySelectorAll('#results b').length") == 0

    # a row measured with warnings reads "ok, warned", its warnings below it (all in the title)
    warned = [row for row in written if row["status"] == "ok" and row.get("warnings")]
    assert {relative(row["file"], folder) for row in warned} & {"saddle.ply", "sub/sphere.ply"}
    for row in warned:
        file = relative(row["file"], folder)
        cell = page.execute_script(
            "const tr = Array.from(document.querySelectorAll('#results tbody tr'))"
            "  .find(r => r.dataset.file === arguments[0]);"
            "const td = tr.querySelector('td.status');"
            "const w = td.querySelector('.cell-warnings');"
            "return [td.firstChild.textContent, w ? w.textContent : null, w ? w.title : null]",
            file,
        )
        assert cell == ["ok, warned", row["warnings"], row["warnings"]], (file, cell)
        item = page.execute_script(
            "const li = Array.from(document.querySelectorAll('#run-files li'))"
            "  .find(l => l.dataset.path === arguments[0]);"
            "return li ? [li.querySelector('.status').textContent, li.textContent] : null",
            file,
        )
        assert item is not None and item[0] == "ok, warned" and row["warnings"] in item[1], item
    unwarned = [row for row in written if row["status"] == "ok" and not row.get("warnings")]
    for row in unwarned:
        text = page.execute_script(
            "const tr = Array.from(document.querySelectorAll('#results tbody tr'))"
            "  .find(r => r.dataset.file === arguments[0]);"
            "return tr.querySelector('td.status').textContent",
            relative(row["file"], folder),
        )
        assert text == "ok"
    # the seconds of each file: 2 significant digits, never "0.0 s"
    times = page.execute_script(
        "return Array.from(document.querySelectorAll('#run-files li .muted'), s => s.textContent)"
    )
    pattern = r" (< 0\.001|[0-9.]+(e[-+]?\d+)?) s"
    assert times and all(re.fullmatch(pattern, t) for t in times), times
    assert not any(t.strip() == "0.0 s" for t in times)

    # the filter hides what does not match
    page.execute_script(
        "const f = document.getElementById('filter'); f.value = 'saddle';"
        "f.dispatchEvent(new Event('input'));"
    )
    visible = page.execute_script(
        "return Array.from(document.querySelectorAll('#results tbody tr'))"
        ".filter(tr => !tr.hidden).map(tr => tr.dataset.file)"
    )
    assert visible == ["saddle.ply"]
    page.execute_script(
        "const f = document.getElementById('filter'); f.value = '';"
        "f.dispatchEvent(new Event('input'));"
    )
    page.execute_script("document.getElementById('measure-section').scrollIntoView()")
    page.save_screenshot(str(shots / "3-run.png"))
    # the long command line and the wide table stay inside the window
    assert not page_too_wide(page)
    assert status(page, "errors") == ""


def test_csv_link_gives_the_table(page, shots, folder):
    link = page.find_element(By.ID, "export-csv")
    href = link.get_attribute("href")
    assert "/api/export/table?format=csv" in href
    code, text = fetch_text(page, href)
    assert code == 200, text
    assert text.startswith("file,")
    rows = list(csv.DictReader(io.StringIO(text)))
    shown = page.execute_script(
        "return Array.from(document.querySelectorAll('#results tbody tr'), tr => tr.dataset.file)"
    )
    assert sorted(relative(row["file"], folder) for row in rows) == sorted(
        relative(name, folder) for name in shown
    )
    assert set(shown) >= READABLE

    page.execute_script("document.getElementById('results-section').scrollIntoView()")
    page.save_screenshot(str(shots / "4-results.png"))
    page.execute_script("window.scrollTo(0, 0)")
    page.save_screenshot(str(shots / "5-top.png"))
    assert all((shots / name).stat().st_size > 0 for name in ("4-results.png", "5-top.png"))
    assert status(page, "errors") == ""


def test_the_progress_shows_the_compile_wait_and_never_goes_back(page, shots):
    notice = "compiling dentopo's kernels for this machine, once: about 30 s"
    draw = (
        "const base = {run: 999999, state: 'running', total: 5, files: {}, log: [],"
        "  exit_code: null, command: ''};"
        "drawRun(Object.assign({}, base, arguments[0]));"
    )

    def progress():
        return page.execute_script(
            "const p = document.getElementById('progress');"
            "const note = p.querySelector('.progress-note');"
            "return [p.querySelector('.progress-text').textContent, note.hidden,"
            "  note.textContent, p.dataset.phase || '']"
        )

    page.execute_script(
        draw, {"serial": 1, "done": 0, "compiling": {"message": notice, "seconds": 12}}
    )
    text, hidden, note, phase = progress()
    assert text == "0 / 5" and not hidden and phase == "compiling"
    assert note == notice + " \u00b7 12 s so far"
    assert notice in page.find_element(By.ID, "progress").text  # shown, not only in the log
    page.execute_script("document.getElementById('progress').scrollIntoView({block: 'center'})")
    page.save_screenshot(str(shots / "6-compiling.png"))
    page.execute_script(draw, {"serial": 3, "done": 2, "compiling": None})
    assert progress() == ["2 / 5", True, "", ""]
    page.execute_script(
        draw, {"serial": 2, "done": 1, "compiling": {"message": notice, "seconds": 5}}
    )
    assert progress() == ["2 / 5", True, "", ""]  # an older answer: never drawn over a newer one
    page.execute_script("getJSON('/api/run').then(drawRun)")  # the real run again
    wait(page, 10, "the real run drawn", lambda d: progress()[0] != "2 / 5")
    assert status(page, "errors") == ""


def test_the_page_says_where_it_writes_and_chooses_another_folder(page, shots, folder):
    default = os.path.realpath(folder / "dentopo-app")
    assert page.find_element(By.ID, "output-where").text == default
    assert page.find_element(By.ID, "output").text == default
    click(page, page.find_element(By.ID, "output-change"))
    box = page.find_element(By.ID, "output-folder")
    assert box.get_attribute("value") == "dentopo-app"
    page.execute_script("document.getElementById('message').hidden = true")
    box.clear()
    box.send_keys("../escape")
    click(page, page.find_element(By.ID, "output-use"))
    wait(page, 10, "the refusal", lambda d: d.find_element(By.ID, "message").is_displayed())
    assert "refused" in page.find_element(By.ID, "message-text").text
    assert page.find_element(By.ID, "output-where").text == default
    assert not (folder.parent / "escape").exists()
    box.clear()
    box.send_keys("second try")
    page.execute_script("document.getElementById('measure-section').scrollIntoView()")
    page.save_screenshot(str(shots / "7-output.png"))
    click(page, page.find_element(By.ID, "output-use"))
    chosen = os.path.realpath(folder / "second try")
    wait(
        page,
        30,
        "the new folder shown",
        lambda d: d.find_element(By.ID, "output-where").text == chosen,
    )
    assert page.find_element(By.ID, "output").text == chosen
    assert page.find_element(By.ID, "table-path").text == os.path.join(chosen, "results.csv")
    wait(
        page,
        30,
        "the other folder's (no) results",
        lambda d: d.find_element(By.ID, "results-empty").is_displayed(),
    )
    assert (folder / "second try" / ".dentopo-output").exists()
    assert not page.find_element(By.ID, "output-form").is_displayed()
    assert status(page, "errors") == ""
