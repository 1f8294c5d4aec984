#!/usr/bin/env bash
# Build the documentation site into docs/_build/html, warnings as errors.
#
# Sets up what it needs from the project's own files: the virtual environment .venv at the
# repository's root (created if missing; CI's test run has made it already) gets the docs
# extra (Sphinx, its extensions and dentopo[all]) installed from pyproject.toml. Every
# notebook and gallery example is executed on the way; pictures render off-screen (VTK
# through EGL or OSMesa: Debian's libegl1 libgl1-mesa-dri libosmesa6, as .ci/run installs).
# Set DENTOPO_DOCS_PYTHON to build with another interpreter that has the docs extra.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
if [ -n "${DENTOPO_DOCS_PYTHON:-}" ]; then
    python="$DENTOPO_DOCS_PYTHON"
else
    [ -x .venv/bin/python ] || python3 -m venv .venv
    .venv/bin/pip install -q -e '.[docs]'
    python=.venv/bin/python
fi
unset DISPLAY WAYLAND_DISPLAY  # no windows: every picture is rendered off-screen
export MPLBACKEND=Agg PYTHONPATH="$root/src${PYTHONPATH:+:$PYTHONPATH}"
# a fresh build each time, so that a page or example removed does not linger
rm -rf docs/_build docs/api/generated docs/gallery docs/jupyter_execute docs/sg_execution_times.rst
start=$SECONDS
"$python" -m sphinx -b html -W --keep-going -q docs docs/_build/html
echo "docs: built docs/_build/html/index.html in $((SECONDS - start)) s"
