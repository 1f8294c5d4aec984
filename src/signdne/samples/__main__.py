"""Rewrite the shipped sample meshes: ``python -m signdne.samples``."""

from . import write_samples

for path in write_samples():
    print(path)
