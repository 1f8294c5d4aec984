"""dentopo's version, read by ``dentopo --version`` without importing the rest.

May import: nothing of dentopo (every subpackage may import it).
"""

__version__ = "0.3.0"
