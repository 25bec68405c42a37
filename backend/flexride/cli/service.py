"""``flexride serve`` and ``flexride worker``: the service commands of the CLI.

:func:`register` adds them to flexride's typer app (``flexride.cli``). Without the CLI wiring
the same commands run as ``python -m flexride.cli.service serve|worker``.

* ``serve`` starts the API with uvicorn (with the time limits on receiving a request and the
  connection limits of :mod:`flexride.api.server`); without a broker it also starts the
  embedded runner (a pool of worker processes on this machine); records and results live
  under ``FLEXRIDE_DATA_DIR``. Invalid settings, a weak ``FLEXRIDE_API_TOKEN`` among them, end it
  with exit code 2 and one line per problem.
* ``worker`` starts a Celery worker (the app in ``worker/``) for ``FLEXRIDE_BROKER_URL``; it
  replaces itself with ``python -m celery`` so that one-thread BLAS settings apply before
  NumPy loads.
"""

from __future__ import annotations

import ipaddress
import os
import signal
import sys
from pathlib import Path
from typing import Annotated

import typer
from pydantic import ValidationError

from flexride.settings import API_PREFIX, Settings, get_settings


def _is_loopback(host: str) -> bool:
    if host in ("localhost", ""):
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def _apply_env(**values: object) -> Settings:
    """Put command-line options into the environment (so spawned workers see them too) and
    return the settings; invalid settings end the command with one line per problem.
    """
    for key, value in values.items():
        if value is not None:
            os.environ[f"FLEXRIDE_{key.upper()}"] = str(value)
    get_settings.cache_clear()
    try:
        return get_settings()
    except ValidationError as exc:
        for err in exc.errors():
            name = "FLEXRIDE_" + "_".join(str(p) for p in err["loc"]).upper()
            typer.echo(f"error: {name}: {err['msg']}", err=True)
        raise typer.Exit(2) from None


def serve(
    host: Annotated[str | None, typer.Option(
        help="Bind address (default 127.0.0.1, or FLEXRIDE_HOST)")] = None,
    port: Annotated[int | None, typer.Option(help="Port (default 8000, or FLEXRIDE_PORT)")] = None,
    workers: Annotated[int | None, typer.Option(
        help="Embedded worker processes (default: number of cores, or FLEXRIDE_WORKERS)")] = None,
    data_dir: Annotated[Path | None, typer.Option(
        help="Directory of the database and the results (FLEXRIDE_DATA_DIR)")] = None,
) -> None:
    """Start the API (and, without a broker, the embedded pool of worker processes)."""
    import uvicorn

    from flexride.jobs.warmup import limit_blas_threads

    limit_blas_threads(1)  # concurrent requests, each single-threaded (submission checks)
    settings = _apply_env(host=host, port=port, workers=workers, data_dir=data_dir)
    bind = settings.bind_host
    if not _is_loopback(bind) and not settings.api_token:
        typer.echo(f"warning: listening on {bind} without FLEXRIDE_API_TOKEN: anyone who can "
                   "reach this address can submit and delete jobs", err=True)
    if not _is_loopback(bind) and not settings.allowed_hosts:
        names = ", ".join(settings.trusted_hosts)
        typer.echo(f"note: only requests for {names} are answered; set FLEXRIDE_ALLOWED_HOSTS "
                   "to the host names clients use (e.g. flexride.example.org)", err=True)
    shown = "127.0.0.1" if bind in ("0.0.0.0", "::") else bind
    url = f"http://{shown}:{settings.port}"
    typer.echo(f"flexride service: API docs at {url}/docs, API at {url}{API_PREFIX}")
    if settings.frontend_dir is not None:
        typer.echo(f"dashboard at {url}/")
    runner = settings.effective_runner
    detail = {"embedded": f"embedded runner with {settings.workers} worker process(es)",
              "celery": "Celery workers via the broker (start them with `flexride worker`)",
              "none": "no runner: jobs are recorded only"}[runner]
    typer.echo(f"jobs: {detail}; data in {settings.data_dir}")
    _exit_normally_on_sigterm()
    from flexride.api.server import ConnectionLimits, protocol_class

    uvicorn.run("flexride.api.main:create_app", factory=True, host=bind, port=settings.port,
                log_level=settings.log_level.lower(), proxy_headers=True,
                http=protocol_class(ConnectionLimits.from_settings(settings)),
                limit_concurrency=settings.max_connections)


def _exit_normally_on_sigterm() -> None:
    """After a graceful shutdown uvicorn raises the signal it caught again with the handler
    it found: SIGTERM's default would end the process at once, skipping the exit handlers
    that release the embedded runner's semaphores. Exit through ``SystemExit`` instead (code
    143 = 128 + SIGTERM, as a process ended by the signal reports).
    """
    def _exit(signum: int, _frame: object) -> None:
        raise SystemExit(128 + signum)

    signal.signal(signal.SIGTERM, _exit)


def _worker_argv(concurrency: int, loglevel: str, queue: str) -> list[str]:
    return [sys.executable, "-m", "celery", "-A", "flexride.jobs.celery_app", "worker",
            f"--concurrency={concurrency}", f"--loglevel={loglevel.upper()}", "-Q", queue,
            "-n", f"flexride-{os.getpid()}@%h", "--without-gossip", "--without-mingle",
            "--pool=prefork"]


def _worker_env() -> dict[str, str]:
    from flexride.jobs.warmup import single_threaded_env

    single_threaded_env()
    return dict(os.environ)


def worker(
    concurrency: Annotated[int | None, typer.Option(
        help="Worker processes (default FLEXRIDE_WORKERS, else the number of cores)")] = None,
    loglevel: Annotated[str | None, typer.Option(help="Log level (FLEXRIDE_LOG_LEVEL)")] = None,
    queue: Annotated[str | None, typer.Option(help="Queue (FLEXRIDE_CELERY_QUEUE)")] = None,
) -> None:
    """Start a Celery worker that runs jobs from FLEXRIDE_BROKER_URL."""
    settings = _apply_env(workers=concurrency, log_level=loglevel, celery_queue=queue)
    if not settings.broker_url:
        typer.echo("error: set FLEXRIDE_BROKER_URL (e.g. redis://127.0.0.1:6379/0) to run a "
                   "worker; without a broker `flexride serve` runs jobs itself", err=True)
        raise typer.Exit(2)
    argv = _worker_argv(settings.workers, settings.log_level, settings.celery_queue)
    typer.echo(f"flexride worker: {settings.workers} process(es), queue "
               f"{settings.celery_queue}, data in {settings.data_dir}", err=True)
    sys.stdout.flush()
    sys.stderr.flush()
    os.execve(sys.executable, argv, _worker_env())


def register(app: typer.Typer) -> None:
    """Add the ``serve`` and ``worker`` commands to ``app`` (flexride's CLI)."""
    app.command("serve")(serve)
    app.command("worker")(worker)


def main() -> None:
    """``python -m flexride.cli.service``: the two commands on their own."""
    app = typer.Typer(add_completion=False, no_args_is_help=True,
                      help="flexride service commands")
    register(app)
    app()


if __name__ == "__main__":
    main()
