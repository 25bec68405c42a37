"""The FastAPI application: routers under ``/api/v1``, error handlers, body-size limit, the
job runner and the reaper started with the app, and the static files (dashboard at ``/`` when
``frontend/`` exists, ``/static/plotly.min.js`` from the installed plotly package).

Run it with ``flexride serve``, or ``uvicorn --factory flexride.api.main:create_app``.
"""

from __future__ import annotations

import logging
from collections.abc import AsyncIterator
from contextlib import asynccontextmanager
from pathlib import Path

from fastapi import FastAPI
from fastapi.middleware.gzip import GZipMiddleware
from fastapi.responses import FileResponse, RedirectResponse
from fastapi.staticfiles import StaticFiles

from flexride import __version__
from flexride.api.deps import Services
from flexride.api.errors import ERROR_RESPONSES, SafeJSONResponse, install_error_handlers
from flexride.api.middleware import BodySizeLimit
from flexride.api.routes import api_router
from flexride.api.schemas import ErrorResponse
from flexride.api.services.fe import FEBuilds
from flexride.jobs.factory import make_runner
from flexride.jobs.reaper import Reaper
from flexride.settings import API_PREFIX, Settings, get_settings
from flexride.store import JobStore, ResultFiles
from flexride.study.submit import Submitter

log = logging.getLogger(__name__)

TAGS = [
    {"name": "jobs", "description": "Submit, follow, cancel and delete simulation jobs."},
    {"name": "results", "description": "Summary, decimated series, spectra, spectrogram, "
     "Sperling breakdown, cross-correlation and the HDF5 file of a finished job."},
    {"name": "studies", "description": "Job matrices over speeds, conditions, body models and "
     "parameters, with tables ready to plot."},
    {"name": "fe", "description": "FE meshes and mode shapes of the flexible car body and "
     "bogie frames, by model parameters or of a job, built in the background."},
    {"name": "presets", "description": "Named scenarios and JSON schemas."},
    {"name": "service", "description": "Health and version."},
]


def build_services(settings: Settings) -> Services:
    """Create the store (schema created or migrated), files, runner, submitter, reaper and the
    FE export builds."""
    store = JobStore.from_url(settings.effective_database_url, create=True)
    files = ResultFiles(settings.results_dir)
    runner = make_runner(settings, store)
    submitter = Submitter(store, files, runner, settings)
    return Services(settings=settings, store=store, files=files, runner=runner,
                    submitter=submitter, reaper=Reaper(store, runner, settings),
                    fe=FEBuilds(settings.cache_dir))


def plotly_js_path() -> Path | None:
    """``plotly.min.js`` of the installed plotly package, if present."""
    try:
        import plotly
    except ImportError:  # pragma: no cover - plotly is a dependency
        return None
    p = Path(plotly.__file__).parent / "package_data" / "plotly.min.js"
    return p if p.is_file() else None


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


def create_app(settings: Settings | None = None) -> FastAPI:
    """The flexride API application.

    Parameters
    ----------
    settings : Settings, optional
        Configuration; read from ``FLEXRIDE_*`` environment variables by default.
    """
    settings = settings or get_settings()
    if not logging.getLogger().handlers:
        logging.basicConfig(level=settings.log_level.upper(),
                            format="%(asctime)s %(levelname)s %(name)s: %(message)s")
    services = build_services(settings)

    @asynccontextmanager
    async def lifespan(_app: FastAPI) -> AsyncIterator[None]:
        services.runner.start()
        services.reaper.start()
        services.fe.start()
        log.info("flexride API %s: runner %s, store %s, results in %s", __version__,
                 services.runner.kind, services.store.engine.url.render_as_string(),
                 services.files.root)
        try:
            yield
        finally:
            services.reaper.stop()
            services.runner.stop()
            services.fe.stop()

    app = FastAPI(
        title="flexride",
        version=__version__,
        description="Ride comfort of metro vehicles with flexible bodies on flexible track: "
        "simulation jobs, studies and their results. Mutating endpoints need "
        "`Authorization: Bearer <token>` when the service has a token.",
        openapi_url=f"{API_PREFIX}/openapi.json",
        docs_url="/docs",
        redoc_url="/redoc",
        openapi_tags=TAGS,
        default_response_class=SafeJSONResponse,
        lifespan=lifespan,
    )
    app.state.services = services
    install_error_handlers(app)
    responses = {code: {**doc, "model": ErrorResponse} for code, doc in ERROR_RESPONSES.items()}
    app.include_router(api_router, prefix=API_PREFIX, responses=responses)
    app.add_middleware(GZipMiddleware, minimum_size=4096, compresslevel=1)
    app.add_middleware(BodySizeLimit, max_bytes=settings.max_body_bytes)
    _static(app, settings)
    return app
