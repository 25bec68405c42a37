"""Service settings from environment variables (prefix ``FLEXRIDE_``) and an optional ``.env``.

Every setting has a working default, so ``flexride serve`` needs no configuration: job records
in SQLite and result files under one data directory, jobs run by an embedded pool of worker
processes. Set ``FLEXRIDE_BROKER_URL`` to send jobs to Celery workers instead
(``flexride worker``), and ``FLEXRIDE_DATABASE_URL`` to keep the records in PostgreSQL. The
table of settings is in ``docs/service.md``.
"""

from __future__ import annotations

import os
from functools import lru_cache
from pathlib import Path
from typing import Literal

from pydantic import Field, computed_field, field_validator
from pydantic_settings import BaseSettings, SettingsConfigDict

API_PREFIX = "/api/v1"
"""Path prefix of every API route."""

_REPO_ROOT = Path(__file__).resolve().parents[2]


def _default_data_dir() -> Path:
    base = os.environ.get("XDG_DATA_HOME") or str(Path.home() / ".local" / "share")
    return Path(base) / "flexride"


def _default_cache_dir() -> Path:
    return Path.home() / ".cache" / "flexride"


def _default_frontend_dir() -> Path | None:
    candidate = _REPO_ROOT / "frontend"
    return candidate if candidate.is_dir() else None


class Settings(BaseSettings):
    """Configuration of the API, the job runners and the workers.

    Attributes are read from ``FLEXRIDE_<NAME>`` environment variables (case-insensitive), e.g.
    ``FLEXRIDE_DATA_DIR``, ``FLEXRIDE_BROKER_URL``, ``FLEXRIDE_WORKERS``.
    """

    model_config = SettingsConfigDict(
        env_prefix="FLEXRIDE_", env_file=".env", env_ignore_empty=True, extra="ignore"
    )

    data_dir: Path = Field(
        default_factory=_default_data_dir,
        description="Directory of the SQLite database (default store) and of results/*.h5",
    )
    database_url: str | None = Field(
        None,
        description="SQLAlchemy URL of the job store, e.g. "
        "postgresql+psycopg://user:pw@host:5432/db; default sqlite:///<data_dir>/flexride.db",
    )
    broker_url: str | None = Field(
        None, description="Celery broker (redis://host:6379/0); unset: embedded runner"
    )
    runner: Literal["auto", "embedded", "celery", "none"] = Field(
        "auto",
        description="auto: celery when a broker URL is set, else embedded; none: record jobs "
        "only (another process runs them)",
    )
    workers: int = Field(
        default_factory=lambda: max(1, os.cpu_count() or 1),
        ge=1,
        le=256,
        description="Embedded pool size, and the default concurrency of `flexride worker`",
    )
    api_token: str | None = Field(
        None, description="Bearer token required by every mutating endpoint when set"
    )
    host: str | None = Field(
        None, description="Bind address of `flexride serve` (default 127.0.0.1)"
    )
    port: int = Field(8000, ge=1, le=65535, description="Port of `flexride serve`")
    max_body_bytes: int = Field(
        4 * 1024 * 1024, ge=1024, description="Largest accepted request body (bytes); 413 beyond"
    )
    max_attempts: int = Field(
        2, ge=1, le=10, description="Starts of a job before a lost worker marks it failed"
    )
    heartbeat_interval_s: float = Field(
        5.0, gt=0.0, le=600.0, description="Seconds between heartbeats of a running job"
    )
    heartbeat_timeout_s: float = Field(
        60.0, gt=0.0, le=86400.0,
        description="A running job without heartbeat for this long has lost its worker",
    )
    reaper_interval_s: float = Field(
        5.0, gt=0.0, le=3600.0, description="Seconds between checks for lost workers"
    )
    job_time_limit_s: float = Field(
        4 * 3600.0, gt=10.0, le=7 * 86400.0,
        description="Hard time limit of one job (s); the soft limit is 95 % of it",
    )
    worker_max_memory_mb: int = Field(
        4096, ge=128, description="A Celery worker child is replaced after exceeding this"
    )
    max_study_jobs: int = Field(256, ge=1, le=100_000, description="Most jobs in one study")
    reuse_results: bool = Field(
        True, description="Reuse stored results of identical scenarios unless a request opts out"
    )
    preflight: bool = Field(
        True, description="Check assembly and time-step stability at submission"
    )
    frontend_dir: Path | None = Field(
        default_factory=_default_frontend_dir,
        description="Static dashboard served at / when the directory exists",
    )
    cache_dir: Path = Field(
        default_factory=_default_cache_dir,
        description="Caches: numba kernels, reduced FE bodies (fem-<version>/) and their "
        "browser exports served by GET /fe (fe-export-<version>/)",
    )
    celery_queue: str = Field("flexride", description="Celery queue of the simulation jobs")
    log_level: str = Field("info", description="Log level of the service and the workers")

    @field_validator("data_dir", "cache_dir", mode="after")
    @classmethod
    def _absolute(cls, value: Path) -> Path:
        return value.expanduser().resolve()

    @computed_field  # type: ignore[prop-decorator]
    @property
    def effective_database_url(self) -> str:
        """The database URL in use (the SQLite default under ``data_dir`` when unset)."""
        return self.database_url or f"sqlite:///{self.data_dir / 'flexride.db'}"

    @computed_field  # type: ignore[prop-decorator]
    @property
    def results_dir(self) -> Path:
        """Directory of the result files (``<data_dir>/results``)."""
        return self.data_dir / "results"

    @computed_field  # type: ignore[prop-decorator]
    @property
    def effective_runner(self) -> str:
        """The runner in use: ``embedded``, ``celery`` or ``none``."""
        if self.runner != "auto":
            return self.runner
        return "celery" if self.broker_url else "embedded"

    @computed_field  # type: ignore[prop-decorator]
    @property
    def bind_host(self) -> str:
        """Address ``flexride serve`` binds to: the setting, else loopback."""
        return self.host or "127.0.0.1"


@lru_cache(maxsize=1)
def get_settings() -> Settings:
    """The process-wide settings (read once from the environment)."""
    return Settings()


def redact_url(url: str | None) -> str | None:
    """``url`` with any password replaced by ``***`` (for health output and logs)."""
    if not url or "@" not in url or "://" not in url:
        return url
    scheme, rest = url.split("://", 1)
    creds, host = rest.rsplit("@", 1)
    if ":" in creds:
        creds = creds.split(":", 1)[0] + ":***"
    return f"{scheme}://{creds}@{host}"
