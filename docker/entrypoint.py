#!/opt/flexride/bin/python
"""Entry point of the flexride image (``flexride-entrypoint``): secrets, then wait, then run.

1. Secrets from files: ``FLEXRIDE_API_TOKEN_FILE`` sets ``FLEXRIDE_API_TOKEN`` from a file
   (e.g. a compose secret under ``/run/secrets``), and ``FLEXRIDE_DATABASE_PASSWORD_FILE`` puts
   the password of that file into ``FLEXRIDE_DATABASE_URL``. A variable set both ways is an
   error; nothing is written anywhere.
2. Waits until the job store (PostgreSQL: a real connection) and the broker (Redis: ``PING``)
   answer, at most ``FLEXRIDE_WAIT_S`` seconds (default 120, ``0`` waits not at all), saying
   once per service what it waits for; gives up with exit code 1 and one line.
3. Replaces itself with the command (``flexride serve`` or ``flexride worker``).
"""

from __future__ import annotations

import os
import socket
import sys
import time
from collections.abc import Callable, MutableMapping
from pathlib import Path
from urllib.parse import urlsplit

PREFIX = "flexride-entrypoint"


def _say(text: str) -> None:
    print(f"{PREFIX}: {text}", file=sys.stderr, flush=True)


def _secret(path: str) -> str:
    """The content of a secret file without its trailing line break."""
    return Path(path).read_text().rstrip("\r\n")


def read_secret_files(env: MutableMapping[str, str]) -> None:
    """Resolve the ``*_FILE`` variables of the token and the database password in ``env``.

    Parameters
    ----------
    env : mutable mapping
        The environment (``os.environ``); changed in place.
    """
    token_file = env.pop("FLEXRIDE_API_TOKEN_FILE", "")
    if token_file:
        if env.get("FLEXRIDE_API_TOKEN"):
            raise SystemExit(f"{PREFIX}: set FLEXRIDE_API_TOKEN or FLEXRIDE_API_TOKEN_FILE, "
                             "not both")
        env["FLEXRIDE_API_TOKEN"] = _secret(token_file)
    password_file = env.pop("FLEXRIDE_DATABASE_PASSWORD_FILE", "")
    if password_file and env.get("FLEXRIDE_DATABASE_URL"):
        from sqlalchemy.engine import make_url

        url = make_url(env["FLEXRIDE_DATABASE_URL"]).set(password=_secret(password_file))
        env["FLEXRIDE_DATABASE_URL"] = url.render_as_string(hide_password=False)


def _postgres_problem(database_url: str) -> str | None:
    """Why PostgreSQL at ``database_url`` does not take a connection yet, or None."""
    import psycopg
    from sqlalchemy.engine import make_url

    url = make_url(database_url).set(drivername="postgresql")
    try:
        psycopg.connect(url.render_as_string(hide_password=False), connect_timeout=3).close()
    except psycopg.Error as exc:
        return str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
    return None


def _redis_problem(broker_url: str) -> str | None:
    """Why Redis at ``broker_url`` does not answer ``PING`` yet, or None."""
    parts = urlsplit(broker_url)
    try:
        with socket.create_connection((parts.hostname or "localhost", parts.port or 6379),
                                      timeout=3) as sock:
            sock.sendall(b"PING\r\n")
            reply = sock.recv(64)
    except OSError as exc:
        return str(exc)
    # +PONG, or -NOAUTH when a password is needed: either way Redis is up
    return None if reply[:1] in (b"+", b"-") else f"unexpected reply {reply!r}"


def _checks(env: MutableMapping[str, str]) -> list[tuple[str, Callable[[], str | None]]]:
    checks: list[tuple[str, Callable[[], str | None]]] = []
    db = env.get("FLEXRIDE_DATABASE_URL", "")
    if db.startswith("postgresql"):
        checks.append(("PostgreSQL", lambda: _postgres_problem(db)))
    broker = env.get("FLEXRIDE_BROKER_URL", "")
    if broker.startswith(("redis://", "rediss://")):
        checks.append(("Redis", lambda: _redis_problem(broker)))
    return checks


def wait_for_services(env: MutableMapping[str, str]) -> None:
    """Wait until the database and the broker of ``env`` answer, or exit with one line.

    Parameters
    ----------
    env : mutable mapping
        The environment; ``FLEXRIDE_WAIT_S`` is the longest wait in seconds.
    """
    limit = float(env.get("FLEXRIDE_WAIT_S") or 120)
    deadline = time.monotonic() + limit
    for name, problem_of in _checks(env) if limit > 0 else []:
        problem, told = problem_of(), False
        while problem is not None:
            if time.monotonic() > deadline:
                raise SystemExit(f"{PREFIX}: {name} is not reachable after {limit:g} s: "
                                 f"{problem}")
            if not told:
                _say(f"waiting for {name} ({problem})")
                told = True
            time.sleep(1.0)
            problem = problem_of()
        if told:
            _say(f"{name} is up")


def main(argv: list[str]) -> None:
    """Resolve secrets, wait for the services, then execute ``argv``."""
    if not argv:
        raise SystemExit(f"{PREFIX}: no command given")
    read_secret_files(os.environ)
    wait_for_services(os.environ)
    os.execvp(argv[0], argv)


if __name__ == "__main__":
    main(sys.argv[1:])
