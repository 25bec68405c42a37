"""Job and study records (SQLAlchemy: SQLite by default, PostgreSQL by URL) and result files
(one HDF5 file per job).
"""

from flexride.store.db import create_store_engine, get_engine, init_db
from flexride.store.files import ChannelData, ResultFiles
from flexride.store.models import FINAL_STATUSES, JOB_KINDS, JOB_STATUSES, Job, Study, WorkerSeen
from flexride.store.repository import Claim, JobStore, now

__all__ = [
    "FINAL_STATUSES",
    "JOB_KINDS",
    "JOB_STATUSES",
    "ChannelData",
    "Claim",
    "Job",
    "JobStore",
    "ResultFiles",
    "Study",
    "WorkerSeen",
    "create_store_engine",
    "get_engine",
    "init_db",
    "now",
]
