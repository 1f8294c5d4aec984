"""What a row's ``error`` says when a step fails: our own message, or an internal error.

dentopo's own errors (a ``ValueError`` or ``TypeError``, naming the problem with
the input or a parameter) are shown as they are.  Anything else that escapes a
step (a ``ZeroDivisionError`` or an ``IndexError`` in a metric, numpy's
``LinAlgError``, scipy's ``QhullError``, a ``RecursionError`` ...) is a
defect of dentopo, not of the mesh, and was shown as a bare Python message
(``ZeroDivisionError: float division by zero``).  It is now named as such,
with the step it happened in: ``internal error in rfi: ZeroDivisionError:
float division by zero; please report``.  Running out of memory is named too
(``out of memory in opcr``).  The batch goes on either way.
"""

from __future__ import annotations

from collections.abc import Callable

from .._optional import MissingExtraError


def own_message(exc: BaseException) -> bool:
    """Whether `exc` is an error whose message is meant for the user.

    A ``ValueError`` or ``TypeError`` (dentopo's own errors are of these types,
    naming the problem with the input or a parameter); a subclass of them
    from another library (numpy's ``LinAlgError``) is not: it is a defect.
    """
    kind = type(exc)
    return kind in (ValueError, TypeError) or (
        issubclass(kind, (ValueError, TypeError)) and kind.__module__.startswith("dentopo")
    )


def internal_error(step: str, exc: BaseException) -> str:
    """``internal error in STEP: KIND: message; please report``."""
    message = " ".join(str(exc).split())
    kind = type(exc).__name__
    return (
        f"internal error in {step}: {kind}"
        + (f": {message}" if message else "")
        + ("; please report")
    )


def failure_reason(
    step: str, exc: BaseException, reason: Callable[[BaseException], str] = str
) -> str:
    """The ``error`` text for `exc`, raised while doing `step` (a metric's name, "reading" ...).

    Our own ``ValueError`` and ``TypeError`` (and a missing extra, an
    ``OSError`` of reading, a ``NotImplementedError`` naming what is not
    implemented) go through `reason`; ``MemoryError`` is ``out of
    memory in STEP``; anything else is an :func:`internal_error`.
    """
    if isinstance(exc, MemoryError):
        return f"out of memory in {step}"
    if isinstance(exc, (MissingExtraError, OSError, NotImplementedError)):
        return reason(exc)  # a missing extra, a file, an option not implemented: not a defect
    if own_message(exc):
        return reason(exc)
    return internal_error(step, exc)


def names_step(reason: str, step: str) -> bool:
    """Whether `reason` (from :func:`failure_reason`) already names `step`."""
    return reason.startswith(f"internal error in {step}:") or reason == f"out of memory in {step}"
