"""``python -m dentopo``: the dentopo command."""

from .cli import run

run()
