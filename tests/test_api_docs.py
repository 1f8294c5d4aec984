"""The API reference lists every public name of ``dentopo``."""

from __future__ import annotations

import re
from pathlib import Path

import dentopo

API = Path(__file__).resolve().parents[1] / "docs" / "api" / "index.md"


def test_every_public_name_is_in_the_api_reference():
    text = API.read_text(encoding="utf-8")
    listed = set(re.findall(r"^   ([A-Za-z_][\w.]*)$", text, flags=re.M))
    missing = sorted(set(dentopo.__all__) - listed - {"__version__"})
    assert not missing, f"add to docs/api/index.md: {missing}"
