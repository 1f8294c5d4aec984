"""``python -m signdne``: the signDNE command."""

from ._cli import run

run()
