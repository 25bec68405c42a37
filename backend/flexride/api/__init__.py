"""The REST API (FastAPI): routers in :mod:`~flexride.api.routes`, the operations they call in
:mod:`~flexride.api.services`, bodies in :mod:`~flexride.api.schemas`.
"""

from flexride.api.main import create_app

__all__ = ["create_app"]
