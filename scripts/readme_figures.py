"""Make the README's pictures, so that their look is reviewed with every change.

Usage (from the repository root, with the project's environment and ``../shared`` beside the
checkout)::

    .venv/bin/python scripts/readme_figures.py            # writes docs/images/*.png
    .venv/bin/python scripts/readme_figures.py --only report

It writes, from the paper's meshes in ``../shared/data/meshes``:

* ``normal-signed.png``: ``normal.ply``'s signed local curvature, the default occlusal view
  (the picture every ``--screenshot`` gives);
* ``robustness-panel.png``: four panels on one colour scale, the same crown meshed at low,
  normal and high resolution and with noise (the paper's robustness set);
* ``report.png`` and ``report-3d.png``: the collection report of the robustness set and
  the six museum specimens (two groups, from their folders), its table and group plots, and
  one specimen's 3D view opened,
  made with the ``dentopo`` command exactly as a user would and photographed in headless
  Chromium (``benchmarks/report_screenshot.py``).

Nothing here is a test: the pictures are for people to look at.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
MESHES = ROOT.parent / "shared" / "data" / "meshes"
OUT = ROOT / "docs" / "images"
ROBUSTNESS = ("low", "normal", "high", "noise2")
FIGURES = ("signed", "panel", "report")


def _mesh(name: str) -> Path:
    path = MESHES / f"{name}.ply"
    if not path.is_file():
        raise SystemExit(f"{path} not found: the pictures need ../shared beside the checkout")
    return path


def signed(out: Path) -> Path:
    from dentopo import render_curvature

    path = out / "normal-signed.png"
    render_curvature(_mesh("normal"), screenshot=path, window_size=(1200, 900))
    return path


def panel(out: Path) -> Path:
    from dentopo import render_panel

    path = out / "robustness-panel.png"
    items = [(_mesh(name), None) for name in ROBUSTNESS]
    render_panel(
        items,
        labels=[f"{name}.ply" for name in ROBUSTNESS],
        screenshot=path,
        window_size=(2000, 800),
    )
    return path


def report(out: Path) -> list[Path]:
    sys.path.insert(0, str(ROOT / "benchmarks"))
    from report_screenshot import screenshot

    with tempfile.TemporaryDirectory() as tmp:
        scans = Path(tmp) / "scans"
        for group, names in {
            "robustness set": ("low", "normal", "high", "noise1", "noise2", "smooth", "low_hole"),
            "museum specimens": sorted(p.stem for p in MESHES.glob("000*.ply")),
        }.items():
            (scans / group).mkdir(parents=True)
            for name in names:
                os.symlink(_mesh(name), scans / group / f"{name}.ply")
        page = Path(tmp) / "report.html"
        command = [sys.executable, "-m", "dentopo", str(scans), "-q"]
        command += ["--metrics", "ariadne,slope,opcr,rfi", "--find-alpha", "--orient", "auto"]
        command += ["-o", str(Path(tmp) / "results.csv"), "--report", str(page)]
        subprocess.run(command, check=False)  # a failed specimen is part of the picture
        if not page.is_file():
            raise SystemExit("the dentopo command wrote no report")
        whole = screenshot(page, out / "report.png", size=(1400, 2200))
        viewer = screenshot(page, out / "report-3d.png", size=(1400, 900), view=11)  # normal.ply
    return [whole, viewer]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", choices=FIGURES, nargs="+", default=FIGURES)
    parser.add_argument("--out", type=Path, default=OUT, help="(default: docs/images)")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    made = {"signed": signed, "panel": panel, "report": report}
    for name in args.only:
        result = made[name](args.out)
        for path in result if isinstance(result, list) else [result]:
            print(path.relative_to(ROOT) if path.is_relative_to(ROOT) else path)


if __name__ == "__main__":
    main()
