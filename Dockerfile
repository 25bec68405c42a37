# flexride service image: the API (`flexride serve`) and the Celery worker (`flexride worker`).
# Build: docker build -t flexride .      Run everything: docker compose up --scale worker=N
FROM python:3.11-slim

ENV PYTHONDONTWRITEBYTECODE=1 \
    PYTHONUNBUFFERED=1 \
    PIP_NO_CACHE_DIR=1 \
    PIP_DISABLE_PIP_VERSION_CHECK=1 \
    FLEXRIDE_DATA_DIR=/data \
    FLEXRIDE_CACHE_DIR=/opt/flexride-cache \
    NUMBA_CACHE_DIR=/opt/flexride-numba

WORKDIR /app

# the locked dependencies first (tools/lock_image.py writes requirements.lock), then the
# package without resolving anything again: an image built later has the same packages
COPY requirements.lock ./
RUN pip install -r requirements.lock
COPY pyproject.toml README.md ./
COPY backend ./backend
RUN pip install --no-deps . && rm -rf build

# the dashboard (static files, served at /)
COPY frontend ./frontend
ENV FLEXRIDE_FRONTEND_DIR=/app/frontend

# compile the numba kernels into the image's own cache (NUMBA_CACHE_DIR, fixed with the image,
# so it stays warm when compose points FLEXRIDE_CACHE_DIR at a shared volume for FE models)
RUN python -c "from flexride.jobs.warmup import warm_numba; warm_numba(); \
import numpy as np; from flexride.api.services.decimate import lttb_indices; \
lttb_indices(np.arange(100.0), np.arange(100.0), 10)" \
    && useradd --create-home --uid 1000 flexride \
    && mkdir -p /data \
    && chown -R flexride /data \
    && mkdir -p /opt/flexride-cache \
    && chmod -R a+rwX /opt/flexride-cache /opt/flexride-numba

USER flexride
VOLUME ["/data"]
EXPOSE 8000

HEALTHCHECK --interval=30s --timeout=5s --start-period=30s --retries=3 \
    CMD python -c "import urllib.request; urllib.request.urlopen('http://127.0.0.1:8000/api/v1/health', timeout=4)"

CMD ["flexride", "serve", "--host", "0.0.0.0", "--port", "8000"]
