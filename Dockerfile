# flexride service image: the API (`flexride serve`) and the Celery worker (`flexride worker`).
#
#   docker build -t flexride .                      # from debian:bookworm-slim (Docker Hub)
#   python3 tools/docker_images.py                  # without a registry: a Debian base made
#                                                   # with debootstrap, then this file
#   docker compose up -d --scale worker=N           # everything (docker-compose.yml)
#
# Stages: `runtime` is Debian with its Python 3.11 and tini; `build` adds a virtual environment
# in /opt/flexride from the lock file (binary wheels only) and flexride itself; the final stage
# copies that environment onto `runtime` with the application and compiles the numba kernels
# into the image. No compiler, pip, pip cache, apt list or build argument reaches it.
ARG BASE_IMAGE=debian:bookworm-slim

# what both stages need: Debian's Python 3.11 and tini (the init process), the user
FROM ${BASE_IMAGE} AS runtime
RUN apt-get update \
    && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends \
       python3 tini \
    && rm -rf /var/lib/apt/lists/* /var/cache/apt/*.bin /var/log/apt /var/log/dpkg.log \
    && useradd --create-home --uid 1000 flexride

FROM runtime AS build
# how pip reaches the package index from the build (tools/docker_images.py passes the host's
# settings): index URLs, trusted hosts and extra CA certificates (PEM text, e.g. of a proxy
# that inspects TLS). All optional; they stay in this stage.
ARG PIP_INDEX_URL
ARG PIP_EXTRA_INDEX_URL
ARG PIP_TRUSTED_HOST
ARG PIP_DEFAULT_TIMEOUT=120
ARG EXTRA_CA_CERTS=""
ENV DEBIAN_FRONTEND=noninteractive \
    PIP_NO_CACHE_DIR=1 \
    PIP_DISABLE_PIP_VERSION_CHECK=1 \
    PIP_CERT=/etc/ssl/certs/ca-certificates.crt
RUN apt-get update \
    && apt-get install -y --no-install-recommends python3-venv ca-certificates \
    && if [ -n "$EXTRA_CA_CERTS" ]; then \
         printf '%s\n' "$EXTRA_CA_CERTS" > /usr/local/share/ca-certificates/build-extra.crt \
         && update-ca-certificates; fi \
    && python3 -m venv /opt/flexride \
    && /opt/flexride/bin/pip install -q --upgrade pip

# the locked dependencies first (tools/lock_image.py writes requirements.lock), then the
# package without resolving anything again: an image built later has the same packages
WORKDIR /src
COPY requirements.lock ./
RUN /opt/flexride/bin/pip install -r requirements.lock --no-deps --only-binary=:all:
COPY pyproject.toml README.md ./
COPY backend ./backend
# then what only building needs goes: pip and setuptools, the packages' own test suites and
# the C++/Cython sources shipped beside their compiled modules (pyfe3d: 40 MB)
RUN /opt/flexride/bin/pip install --no-deps . \
    && /opt/flexride/bin/pip check \
    && /opt/flexride/bin/pip uninstall -y -q pip setuptools \
    && site=/opt/flexride/lib/python3.11/site-packages \
    && find "$site" -depth -type d -name tests -exec rm -rf {} + \
    && find "$site" -type f \( -name '*.pyx' -o -name '*.pxd' -o -name '*.cpp' -o -name '*.c' \) \
       -delete

FROM runtime
ENV PATH=/opt/flexride/bin:$PATH \
    PYTHONDONTWRITEBYTECODE=1 \
    PYTHONUNBUFFERED=1 \
    FLEXRIDE_DATA_DIR=/data \
    FLEXRIDE_CACHE_DIR=/opt/flexride-cache \
    NUMBA_CACHE_DIR=/opt/flexride-numba
COPY --from=build /opt/flexride /opt/flexride

# compile the numba kernels into the image's own cache (NUMBA_CACHE_DIR, fixed with the image,
# so it stays warm when compose points FLEXRIDE_CACHE_DIR at a shared volume for FE models);
# before the dashboard and the scripts, so that a change of those compiles nothing again
RUN python -c "from flexride.jobs.warmup import warm_numba; warm_numba(); \
import numpy as np; from flexride.api.services.decimate import lttb_indices; \
lttb_indices(np.arange(100.0), np.arange(100.0), 10)" \
    && mkdir -p /data /opt/flexride-cache \
    && chown -R flexride /data \
    && chmod -R a+rwX /opt/flexride-cache /opt/flexride-numba

# the dashboard (static files, served at /)
WORKDIR /app
COPY frontend ./frontend
ENV FLEXRIDE_FRONTEND_DIR=/app/frontend

# the entry point (secrets from *_FILE variables, waits for the database and the broker) and
# the health check of the API and the workers (docker-compose.yml)
COPY docker/entrypoint.py /usr/local/bin/flexride-entrypoint
COPY docker/healthcheck.py /usr/local/bin/flexride-healthcheck
RUN chmod 755 /usr/local/bin/flexride-entrypoint /usr/local/bin/flexride-healthcheck

USER flexride
VOLUME ["/data"]
EXPOSE 8000

HEALTHCHECK --interval=30s --timeout=5s --start-period=30s --retries=3 \
    CMD ["flexride-healthcheck", "api"]

ENTRYPOINT ["tini", "--", "flexride-entrypoint"]
CMD ["flexride", "serve", "--host", "0.0.0.0", "--port", "8000"]
