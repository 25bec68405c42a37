"""Log lines of periodic work (the reaper's passes, a worker's presence reports and claims)
that fails again and again, e.g. while the database refuses writes: one line when it starts
failing or its reason changes, one when it works again, nothing for the same failure repeated
every few seconds.
"""

from __future__ import annotations

import logging

from flexride.store.probe import db_fault, is_storage_oserror, os_fault


def failure_reason(exc: BaseException) -> tuple[str, bool]:
    """Why periodic work failed, and whether that is a known storage fault (a database that
    cannot take writes, a read-only or full disk) rather than a defect.
    """
    fault = db_fault(exc)
    if fault is not None:
        return fault, True
    if isinstance(exc, OSError) and is_storage_oserror(exc):
        return os_fault(exc), True
    first = (str(exc).strip().splitlines() or [""])[0][:200]
    return f"{type(exc).__name__}: {first}", False


class FaultLog:
    """One log line per change of state of a repeated operation.

    Parameters
    ----------
    logger : logging.Logger
        Where the lines go.
    what : str
        The operation, as the lines name it (``reaper pass``).
    """

    def __init__(self, logger: logging.Logger, what: str):
        self.logger, self.what = logger, what
        self.reason: str | None = None

    def failed(self, exc: BaseException) -> None:
        """Record a failure: logged (a warning; with the traceback when it is not a storage
        fault) unless the last failure had the same reason.
        """
        reason, storage = failure_reason(exc)
        if reason == self.reason:
            return
        self.reason = reason
        self.logger.warning("%s failed: %s%s", self.what, reason,
                            "" if storage else " (repeats are not logged)",
                            exc_info=None if storage else exc)

    def succeeded(self) -> None:
        """Record a success: logged once after failures."""
        if self.reason is not None:
            self.logger.info("%s works again (it failed: %s)", self.what, self.reason)
            self.reason = None
