"""The app's refusals: a request it cannot do, with the message the page shows."""

from __future__ import annotations


class AppError(ValueError):
    """A request the app cannot do (a wrong parameter, a run going): its message is shown."""

    def __init__(self, message: str, status: int = 400):
        super().__init__(message)
        self.status = status
