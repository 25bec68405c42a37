"""Job runners: the interface (:mod:`~flexride.jobs.base`), the embedded process pool, the
Celery client and its configuration, recovery of lost jobs and worker presence.
"""

from flexride.jobs.base import JobRunner, NullRunner
from flexride.jobs.factory import make_runner

__all__ = ["JobRunner", "NullRunner", "make_runner"]
