"""A package's public names imported on first use (PEP 562), for its ``__init__``.

May import: nothing of dentopo (every package's ``__init__`` may import it).
"""

from __future__ import annotations

import importlib
import sys


def lazy_exports(package: str, exports: dict[str, str], names):
    """``__getattr__`` and ``__dir__`` for `package`: ``exports`` maps each name to its module.

    A name is imported from its module (relative to `package`) the first time it
    is read, and kept in the package's namespace, so that later reads are plain
    lookups.  ``__dir__`` lists the namespace and `names` (the package's ``__all__``).
    """
    namespace = vars(sys.modules[package])

    def getattr_(name: str):
        module = exports.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(module, package), name)
        namespace[name] = value
        return value

    def dir_() -> list[str]:
        return sorted(set(namespace) | set(names))

    return getattr_, dir_
