"""Rewrite the shipped sample meshes: ``python -m dentopo.samples``."""

from . import write_samples

for path in write_samples():
    print(path)
