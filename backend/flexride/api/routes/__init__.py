"""The API routers, one module per resource."""

from fastapi import APIRouter

from flexride.api.routes import (
    contact,
    estimates,
    fe,
    health,
    jobs,
    presets,
    profiles,
    results,
    studies,
    uploads,
)

api_router = APIRouter()
api_router.include_router(jobs.router)
api_router.include_router(results.router)
api_router.include_router(studies.router)
api_router.include_router(fe.router)
api_router.include_router(uploads.router)
api_router.include_router(profiles.router)
api_router.include_router(contact.router)
api_router.include_router(estimates.router)
api_router.include_router(presets.router)
api_router.include_router(health.router)

__all__ = ["api_router"]
