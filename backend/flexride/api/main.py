"""The FastAPI application: routers under ``/api/v1``, error handlers, the middleware (Host
check, complete ``Allow`` on 405, the token checked before the body, body-size limit), the
job runner and the reaper started with
the app, the API docs (``/docs``, ``/redoc``: their assets served from the installed
``fastapi-offline`` package, no CDN) and the static files (dashboard at ``/`` when
``frontend/`` exists, ``/static/plotly.min.js`` from the installed plotly package).

Run it with ``flexride serve``, or ``uvicorn --factory flexride.api.main:create_app``.
"""

from __future__ import annotations

import base64
import gc
import hashlib
import logging
import re
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from functools import partial
from pathlib import Path

import anyio.to_thread
from fastapi import FastAPI, Request
from fastapi.datastructures import Default
from fastapi.middleware.gzip import GZipMiddleware
from fastapi.openapi.docs import get_redoc_html, get_swagger_ui_html
from fastapi.responses import FileResponse, HTMLResponse, RedirectResponse
from fastapi.staticfiles import StaticFiles

from flexride import __version__
from flexride.api.deps import Services, authorized, needs_token
from flexride.api.errors import ERROR_RESPONSES, SafeJSONResponse, install_error_handlers
from flexride.api.logs import configure_logging
from flexride.api.middleware import BodySizeLimit, MethodNotAllowed, TokenGate, TrustedHosts
from flexride.api.routes import api_router
from flexride.api.schemas import ErrorResponse
from flexride.api.services.fe import FEExports
from flexride.api.services.jobs import sweep_deleted
from flexride.api.services.studies import queue_due_reports
from flexride.jobs.factory import make_runner
from flexride.jobs.reaper import Reaper
from flexride.settings import API_PREFIX, Settings, get_settings, token_problem, url_location
from flexride.store import JobStore, ResultFiles
from flexride.study.submit import Submitter

log = logging.getLogger(__name__)

DOCS_ASSETS_URL = "/static/docs"
"""Where the Swagger UI and ReDoc files of ``fastapi-offline`` are served."""
_INLINE_SCRIPT = re.compile(r"<script>(.*?)</script>", re.S)

TAGS = [
    {"name": "jobs", "description": "Submit, follow, cancel and delete simulation jobs."},
    {"name": "results", "description": "Summary, decimated series, spectra, spectrogram, "
     "Sperling breakdown, cross-correlation and the HDF5 file of a finished job."},
    {"name": "studies", "description": "Job matrices over speeds, conditions, body models and "
     "parameters, with tables ready to plot."},
    {"name": "fe", "description": "FE meshes and mode shapes of the flexible car body and "
     "bogie frames, by model parameters or of a job, built by jobs of kind fe_export."},
    {"name": "uploads", "description": "Measured track irregularities (CSV) and wheel or "
     "rail profiles (SIMPACK, MiniProf, text) uploaded as data, stored by content hash and "
     "referred to by that id in scenarios."},
    {"name": "contact", "description": "Wheel–rail contact geometry of a profile pair "
     "(built in or uploaded): Δr, contact angles, roll and contact points against the "
     "wheelset's lateral displacement, EN 15302 equivalent conicity, profiles for drawing."},
    {"name": "estimates", "description": "Frequency-domain ride-comfort estimates "
     "(the linearised vehicle–track model driven by the track spectra), answered at once, "
     "and parameter sweeps of them."},
    {"name": "presets", "description": "Named scenarios and JSON schemas."},
    {"name": "service", "description": "Health and version."},
]


def build_services(settings: Settings) -> Services:
    """Create the store (schema created or migrated), files, runner, submitter, reaper and the
    FE exports (served from files, built by ``fe_export`` jobs of the runner).
    """
    store = JobStore.from_url(settings.effective_database_url, create=True)
    files = ResultFiles(settings.results_dir,
                        cache_bytes=int(settings.result_cache_mb * 1024 * 1024))
    runner = make_runner(settings, store)
    submitter = Submitter(store, files, runner, settings)
    svc = Services(settings=settings, store=store, files=files, runner=runner,
                   submitter=submitter, reaper=Reaper(store, runner, settings),
                   fe=FEExports(store, submitter, settings.cache_dir,
                                wait_s=settings.fe_wait_s),
                   uploads=submitter.uploads)
    svc.reaper.hooks.append(partial(queue_due_reports, svc))
    return svc


def plotly_js_path() -> Path | None:
    """``plotly.min.js`` of the installed plotly package, if present."""
    try:
        import plotly
    except ImportError:  # pragma: no cover - plotly is a dependency
        return None
    p = Path(plotly.__file__).parent / "package_data" / "plotly.min.js"
    return p if p.is_file() else None


def docs_assets_dir() -> Path | None:
    """The Swagger UI and ReDoc files (``swagger-ui-bundle.js``, ``swagger-ui.css``,
    ``redoc.standalone.js``, ``favicon.png``) of the installed ``fastapi-offline`` package.
    """
    try:
        import fastapi_offline
    except ImportError:  # pragma: no cover - fastapi-offline is a dependency
        return None
    p = Path(fastapi_offline.__file__).parent / "static"
    return p if (p / "swagger-ui-bundle.js").is_file() else None


def _same_origin_only(page: HTMLResponse) -> HTMLResponse:
    """``page`` with a Content-Security-Policy that lets it load nothing from elsewhere (ReDoc
    would fetch its logo from cdn.redoc.ly) and run only its own scripts (inline ones by
    hash).
    """
    html = page.body.decode() if isinstance(page.body, bytes) else str(page.body)
    scripts = " ".join(["'self'", *(
        "'sha256-" + base64.b64encode(hashlib.sha256(s.encode()).digest()).decode() + "'"
        for s in _INLINE_SCRIPT.findall(html))])
    page.headers["Content-Security-Policy"] = (
        f"default-src 'self'; script-src {scripts}; style-src 'self' 'unsafe-inline'; "
        "img-src 'self' data:; font-src 'self' data:; worker-src 'self' blob:; "
        "object-src 'none'; base-uri 'none'; frame-ancestors 'self'")
    return page


def _docs(app: FastAPI) -> None:
    """``/docs`` (Swagger UI) and ``/redoc`` (ReDoc) loading their scripts, styles and icon
    from this service (``DOCS_ASSETS_URL``) instead of a CDN, so they work offline.
    """
    assets = docs_assets_dir()
    if assets is None:  # pragma: no cover
        log.warning("fastapi-offline is not installed: /docs and /redoc have no scripts")
    else:
        app.mount(DOCS_ASSETS_URL, StaticFiles(directory=assets), name="docs-assets")
    openapi_url = app.openapi_url or f"{API_PREFIX}/openapi.json"

    async def swagger_ui(request: Request) -> HTMLResponse:
        root = request.scope.get("root_path", "") + DOCS_ASSETS_URL
        return _same_origin_only(get_swagger_ui_html(
            openapi_url=request.scope.get("root_path", "") + openapi_url,
            title=f"{app.title} - Swagger UI", swagger_js_url=f"{root}/swagger-ui-bundle.js",
            swagger_css_url=f"{root}/swagger-ui.css", swagger_favicon_url=f"{root}/favicon.png",
            # no badge image from validator.swagger.io
            swagger_ui_parameters={"validatorUrl": None}))

    async def redoc(request: Request) -> HTMLResponse:
        root = request.scope.get("root_path", "") + DOCS_ASSETS_URL
        return _same_origin_only(get_redoc_html(
            openapi_url=request.scope.get("root_path", "") + openapi_url,
            title=f"{app.title} - ReDoc", redoc_js_url=f"{root}/redoc.standalone.js",
            redoc_favicon_url=f"{root}/favicon.png", with_google_fonts=False))

    app.add_route("/docs", swagger_ui, include_in_schema=False)
    app.add_route("/redoc", redoc, include_in_schema=False)


def _static(app: FastAPI, settings: Settings) -> None:
    js = plotly_js_path()

    @app.get("/static/plotly.min.js", include_in_schema=False)
    def plotly_js() -> FileResponse:
        if js is None:
            from flexride.api.errors import NotFound

            raise NotFound("plotly.min.js is not installed")
        return FileResponse(js, media_type="application/javascript",
                            headers={"Cache-Control": "public, max-age=86400"})

    frontend = settings.frontend_dir
    if frontend is not None and Path(frontend).is_dir():
        app.mount("/", StaticFiles(directory=frontend, html=True), name="frontend")
    else:
        @app.get("/", include_in_schema=False)
        def root() -> RedirectResponse:
            return RedirectResponse("/docs")


def limits_text(settings: Settings) -> str:
    """The service's bounds on requests, for the API description (markdown)."""
    s = settings
    return ("**Limits of this service** (422 beyond them, naming the field, the estimate and "
            "the limit): "
            f"{s.max_steps:,} time steps per job (`FLEXRIDE_MAX_STEPS`); "
            f"{s.max_output_points} recorded car-body points (`FLEXRIDE_MAX_OUTPUT_POINTS`); "
            f"{s.max_result_mb:g} MB of results (`FLEXRIDE_MAX_RESULT_MB`); FE bodies up to "
            f"{s.max_fe_dofs:,} degrees of freedom and {s.max_fe_cutoff_hz:g} Hz "
            "(`FLEXRIDE_MAX_FE_DOFS`, `FLEXRIDE_MAX_FE_CUTOFF_HZ`); "
            f"{s.max_study_jobs} jobs per study (`FLEXRIDE_MAX_STUDY_JOBS`); request bodies "
            f"and uploads up to {s.max_body_bytes:,} bytes (413, `FLEXRIDE_MAX_BODY_BYTES`). "
            "**Connections** (`flexride serve`): a request's headers within "
            f"{s.header_timeout_s:g} s, its body with pauses of at most "
            f"{s.body_idle_timeout_s:g} s and within {s.body_timeout_s:g} s (408); "
            f"{s.max_connections_per_client} connections per client address at once (429).")


def create_app(settings: Settings | None = None) -> FastAPI:
    """The flexride API application.

    Parameters
    ----------
    settings : Settings, optional
        Configuration; read from ``FLEXRIDE_*`` environment variables by default.

    Raises
    ------
    ValueError
        When the settings carry a weak API token (see :func:`flexride.settings.token_problem`).
    """
    settings = settings or get_settings()
    problem = token_problem(settings.api_token)
    if problem:  # settings made without validation (Settings() itself refuses it)
        raise ValueError(f"FLEXRIDE_API_TOKEN: {problem}")
    configure_logging(settings.log_level)
    services = build_services(settings)

    @asynccontextmanager
    async def lifespan(_app: FastAPI) -> AsyncIterator[None]:
        # threads of the synchronous routes: fewer than AnyIO's default of 40, because on a
        # machine of a few cores they only contend for the GIL (measured: less CPU per
        # request, shorter tails under 50 concurrent readers)
        anyio.to_thread.current_default_thread_limiter().total_tokens = settings.api_threads
        sweep_deleted(services)
        services.runner.start()
        services.reaper.start()
        if settings.gc_freeze:
            # everything made so far (modules, the app, schemas, the store) lives as long as
            # the process: keep it out of the collector's full passes, which otherwise stalled
            # every request in flight for ~0.1 s now and then (p99 of 50 readers 239 → 84 ms)
            gc.freeze()
        log.info("flexride API %s: runner %s, store %s, results in %s", __version__,
                 services.runner.kind, url_location(settings.effective_database_url),
                 services.files.root)
        try:
            yield
        finally:
            services.reaper.stop()
            services.runner.stop()

    app = FastAPI(
        title="flexride",
        version=__version__,
        description="Ride comfort of metro vehicles with flexible bodies on flexible track: "
        "simulation jobs, studies and their results. Mutating endpoints need "
        "`Authorization: Bearer <token>` when the service has a token.\n\n"
        + limits_text(settings),
        openapi_url=f"{API_PREFIX}/openapi.json",
        docs_url=None,  # served by _docs, without a CDN
        redoc_url=None,
        openapi_tags=TAGS,
        # a placeholder keeps FastAPI's fast path (Pydantic writes the JSON, non-finite
        # floats as null) for routes with a response model; SafeJSONResponse for the rest
        default_response_class=Default(SafeJSONResponse),
        lifespan=lifespan,
    )
    app.state.services = services
    install_error_handlers(app)
    responses = {code: {**doc, "model": ErrorResponse} for code, doc in ERROR_RESPONSES.items()}
    app.include_router(api_router, prefix=API_PREFIX, responses=responses)
    app.add_middleware(GZipMiddleware, minimum_size=4096, compresslevel=1)
    app.add_middleware(BodySizeLimit, max_bytes=settings.max_body_bytes)
    app.add_middleware(TokenGate, router=app.router, needs_token=needs_token,
                       authorized=partial(authorized, settings.api_token))
    app.add_middleware(MethodNotAllowed, router=app.router)
    app.add_middleware(TrustedHosts, allowed=settings.trusted_hosts)
    _docs(app)
    _static(app, settings)
    return app
