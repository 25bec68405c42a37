"""Service settings from environment variables (prefix ``FLEXRIDE_``) and an optional ``.env``.

Every setting has a working default, so ``flexride serve`` needs no configuration: job records
in SQLite and result files under one data directory, jobs run by an embedded pool of worker
processes. Set ``FLEXRIDE_BROKER_URL`` to send jobs to Celery workers instead
(``flexride worker``), and ``FLEXRIDE_DATABASE_URL`` to keep the records in PostgreSQL. The
table of settings is in ``docs/service.md``.
"""

from __future__ import annotations

import os
import re
from functools import lru_cache
from pathlib import Path, PurePosixPath
from typing import Literal
from urllib.parse import urlsplit

from pydantic import Field, computed_field, field_validator
from pydantic_core import PydanticCustomError
from pydantic_settings import BaseSettings, SettingsConfigDict

from flexride.fileio import cache_root

API_PREFIX = "/api/v1"
"""Path prefix of every API route."""

_REPO_ROOT = Path(__file__).resolve().parents[2]

MIN_TOKEN_LENGTH = 16
"""Shortest accepted ``FLEXRIDE_API_TOKEN``."""
TOKEN_HINT = 'make a strong one with: python3 -c "import secrets; print(secrets.token_urlsafe(32))"'
"""How to make a good token (said with every refused one)."""
_WEAK_WORDS = (
    "changeme", "secret", "password", "passw0rd", "p@ssw0rd", "token", "admin", "test",
    "letmein", "qwerty", "welcome", "default", "flexride", "example", "guest", "login",
    "master", "root", "pass", "demo", "user", "bearer", "dummy", "sample", "hello", "api",
)
_WEAK_TOKEN = re.compile("(?:" + "|".join(map(re.escape, _WEAK_WORDS)) + r"|[0-9]|[^a-z0-9])+")
_RUNS = ("abcdefghijklmnopqrstuvwxyz", "qwertyuiopasdfghjklzxcvbnm", "0123456789")
LOOPBACK_HOSTS = ("localhost", "127.0.0.1", "::1")
"""Host names every service accepts (``Host`` header checks, see ``trusted_hosts``)."""
_HOST_ENTRY = re.compile(r"(\*|(\*\.)?[a-z0-9_.-]+|\[[0-9a-f:.]+\]|[0-9a-f:.]+)(:[0-9]{1,5})?")


def _guessable(token: str) -> bool:
    """Whether ``token`` is made of well-known words, digits and punctuation only, of fewer
    than six different characters, or is a run of the alphabet, the keyboard or the digits.
    """
    low = token.lower()
    if _WEAK_TOKEN.fullmatch(low) or len(set(low)) < 6:
        return True
    alnum = re.sub(r"[^a-z0-9]", "", low)
    reps = len(alnum) // 10 + 2
    return any(alnum in run * reps or alnum in run[::-1] * reps for run in _RUNS)


def token_problem(token: str | None) -> str | None:
    """What is wrong with an API token, or None when it is acceptable (or unset).

    Parameters
    ----------
    token : str or None
        The value of ``FLEXRIDE_API_TOKEN``.

    Returns
    -------
    str or None
        One sentence that ends with how to make a strong token (:data:`TOKEN_HINT`).
    """
    if token is None:
        return None
    if not token.strip():
        problem = "is only whitespace"
    elif token != token.strip():
        problem = "begins or ends with whitespace"
    elif not all("!" <= c <= "~" for c in token):
        problem = "must be printable ASCII without spaces"
    elif len(token) < MIN_TOKEN_LENGTH:
        problem = f"is too short ({len(token)} characters, at least {MIN_TOKEN_LENGTH})"
    elif _guessable(token):
        problem = "is a well-known or easily guessed value"
    else:
        return None
    return f"the token {problem}; {TOKEN_HINT}"


def _default_data_dir() -> Path:
    base = os.environ.get("XDG_DATA_HOME") or str(Path.home() / ".local" / "share")
    return Path(base) / "flexride"


def _default_cache_dir() -> Path:
    return cache_root()


def _default_frontend_dir() -> Path | None:
    candidate = _REPO_ROOT / "frontend"
    return candidate if candidate.is_dir() else None


class Settings(BaseSettings):
    """Configuration of the API, the job runners and the workers.

    Attributes are read from ``FLEXRIDE_<NAME>`` environment variables (case-insensitive), e.g.
    ``FLEXRIDE_DATA_DIR``, ``FLEXRIDE_BROKER_URL``, ``FLEXRIDE_WORKERS``.
    """

    model_config = SettingsConfigDict(
        env_prefix="FLEXRIDE_", env_file=".env", env_ignore_empty=True, extra="ignore",
        hide_input_in_errors=True,  # error texts never repeat a value (the token)
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
    allowed_hosts: str | None = Field(
        None,
        description="Host names the API answers besides the bind address, localhost, "
        "127.0.0.1 and ::1 (comma-separated; *.example.org for subdomains, * for any); "
        "other Host headers get 400",
    )
    max_body_bytes: int = Field(
        4 * 1024 * 1024, ge=1024, description="Largest accepted request body (bytes); 413 beyond"
    )
    header_timeout_s: float = Field(
        10.0, gt=0.0, le=600.0,
        description="Time a client has to send a request's line and headers (s); 408 and the "
        "connection closed beyond",
    )
    body_idle_timeout_s: float = Field(
        10.0, gt=0.0, le=600.0,
        description="Longest pause while a request's body arrives (s); 408 beyond",
    )
    body_timeout_s: float = Field(
        120.0, gt=0.0, le=3600.0,
        description="Time a client has to send a whole request body (s); 408 beyond",
    )
    max_connections_per_client: int = Field(
        64, ge=1, le=100_000,
        description="Open connections one client address may hold at once; a request on one "
        "more gets 429",
    )
    max_connections: int = Field(
        1024, ge=1, le=1_000_000,
        description="Open connections the API serves at once (all clients); requests beyond "
        "get 503",
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
    max_steps: int = Field(
        5_000_000, ge=1000, le=10**10,
        description="Most time steps of one job (duration / solver.dt); 422 beyond",
    )
    max_output_points: int = Field(
        200, ge=6, le=100_000,
        description="Most recorded car-body points of one job (the paper's six, user points "
        "and the floor grid); 422 beyond",
    )
    max_result_mb: float = Field(
        512.0, gt=0.0, le=1.0e6,
        description="Largest estimated result file of one job (MB: channels × samples × 8 "
        "bytes); 422 beyond",
    )
    max_fe_dofs: int = Field(
        150_000, ge=1000, le=10**8,
        description="Largest FE model (degrees of freedom, estimated from the element size) a "
        "job or GET /fe may build; 422 beyond",
    )
    max_fe_cutoff_hz: float = Field(
        100.0, gt=1.0, le=500.0,
        description="Highest modal cut-off (Hz) of an FE body a job or GET /fe may build; 422 "
        "beyond",
    )
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
    result_cache_mb: float = Field(
        256.0, ge=0.0, le=1.0e6,
        description="Memory for result-file contents kept between requests (MB)",
    )
    response_cache_mb: float = Field(
        64.0, ge=0.0, le=1.0e6,
        description="Memory for rendered answers of finished jobs kept between requests (MB)",
    )
    api_threads: int = Field(
        8, ge=1, le=256,
        description="Threads of the API for its synchronous routes (reads of the store and "
        "the result files)",
    )
    gc_freeze: bool = Field(
        True,
        description="Exclude the objects made at start-up (they live as long as the process) "
        "from Python's full garbage collections, whose pauses otherwise stalled every request "
        "in flight for about 0.1 s now and then",
    )
    fe_wait_s: float = Field(
        3.0, ge=0.0, le=60.0,
        description="How long GET /fe waits for a running FE build before answering 202 (s)",
    )
    celery_queue: str = Field("flexride", description="Celery queue of the simulation jobs")
    log_level: str = Field("info", description="Log level of the service and the workers")

    @field_validator("api_token", mode="after")
    @classmethod
    def _strong_token(cls, value: str | None) -> str | None:
        if value == "":
            return None  # as an empty FLEXRIDE_API_TOKEN: no token
        problem = token_problem(value)
        if problem:
            raise PydanticCustomError("weak_token", problem)
        return value

    @field_validator("allowed_hosts", mode="before")
    @classmethod
    def _host_list(cls, value: object) -> object:
        if isinstance(value, list | tuple | set):
            value = ",".join(map(str, value))
        if isinstance(value, str):
            for entry in filter(None, (e.strip().lower() for e in value.split(","))):
                if not _HOST_ENTRY.fullmatch(entry):
                    raise PydanticCustomError(
                        "host_list", "'{entry}' is not a host name; give names such as "
                        "api.example.org, comma-separated (no scheme, path or spaces)",
                        {"entry": entry[:60]})
        return value

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
    def uploads_dir(self) -> Path:
        """Directory of uploaded data, stored by content hash (``<data_dir>/uploads``)."""
        return self.data_dir / "uploads"

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

    @computed_field  # type: ignore[prop-decorator]
    @property
    def trusted_hosts(self) -> list[str]:
        """Host names the API answers: localhost, 127.0.0.1, ::1, the bind address (unless
        it is a wildcard address) and ``allowed_hosts``.
        """
        names = [*LOOPBACK_HOSTS]
        if self.bind_host not in ("0.0.0.0", "::", ""):
            names.append(self.bind_host)
        names += [e.strip() for e in (self.allowed_hosts or "").split(",") if e.strip()]
        return list(dict.fromkeys(n.lower() for n in names))


@lru_cache(maxsize=1)
def get_settings() -> Settings:
    """The process-wide settings (read once from the environment)."""
    return Settings()


def url_location(url: str | None) -> str | None:
    """Where ``url`` points, for health answers: scheme, host, port and database, without
    user, password, query, or a file's directory (no server path).

    Examples
    --------
    >>> url_location("postgresql+psycopg://u:secret@db:5432/flexride?options=-cx%3Dy")
    'postgresql://db:5432/flexride'
    >>> url_location("sqlite:////srv/flexride/flexride.db")
    'sqlite:flexride.db'
    >>> url_location("redis://:secret@cache:6379/0")
    'redis://cache:6379/0'
    """
    if not url:
        return url
    parts = urlsplit(url)
    scheme = parts.scheme.split("+", 1)[0]
    if scheme == "sqlite":
        return f"sqlite:{PurePosixPath(parts.path).name or ':memory:'}"
    host = parts.hostname or ""
    try:
        port = f":{parts.port}" if parts.port else ""
    except ValueError:
        port = ""
    return f"{scheme}://{f'[{host}]' if ':' in host else host}{port}{parts.path}"
