"""Screenshots of an HTML page (the collection report) in headless Chromium.

Usage (from the repository root)::

    python benchmarks/report_screenshot.py report.html report.png
    python benchmarks/report_screenshot.py report.html viewer.png --view 3   # specimen 3's 3D view
    python benchmarks/report_screenshot.py report.html full.png --size 1400 3000

Needs Debian's ``chromium`` (or ``chromium-browser``) on the PATH.  WebGL (the
3D view, the scatter matrix) is rendered in software (SwiftShader), so the
picture does not depend on a GPU.  :func:`screenshot` is the reusable piece.
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import tempfile
from pathlib import Path


def screenshot(
    page: str | Path,
    png: str | Path,
    *,
    size: tuple[int, int] = (1400, 1000),
    view: int | None = None,
    budget_ms: int = 8000,
) -> Path:
    """Save a screenshot of `page` (an HTML file) to `png`; `view` opens that specimen's 3D view.

    Raises
    ------
    FileNotFoundError
        If Chromium is not installed.
    subprocess.CalledProcessError
        If Chromium fails.
    """
    chromium = shutil.which("chromium") or shutil.which("chromium-browser")
    if chromium is None:
        raise FileNotFoundError("headless Chromium (Debian package 'chromium') is not installed")
    url = Path(page).resolve().as_uri() + (f"#view={view}" if view is not None else "")
    png = Path(png).resolve()
    with tempfile.TemporaryDirectory() as profile:
        subprocess.run(
            [
                chromium,
                "--headless",
                "--no-sandbox",
                "--disable-gpu",
                "--use-gl=swiftshader",
                "--enable-unsafe-swiftshader",
                "--hide-scrollbars",
                f"--user-data-dir={profile}",
                f"--window-size={size[0]},{size[1]}",
                f"--virtual-time-budget={budget_ms}",
                f"--screenshot={png}",
                url,
            ],
            check=True,
            capture_output=True,
            timeout=180,
        )
    return png


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("page")
    parser.add_argument("png")
    parser.add_argument("--size", nargs=2, type=int, default=(1400, 1000), metavar=("W", "H"))
    parser.add_argument("--view", type=int, help="open the 3D view of specimen N (row N+1)")
    args = parser.parse_args()
    print(screenshot(args.page, args.png, size=tuple(args.size), view=args.view))


if __name__ == "__main__":
    main()
