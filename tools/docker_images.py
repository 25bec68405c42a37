#!/usr/bin/env python3
"""Build every image of ``docker-compose.yml`` without a container registry.

Docker Hub is not needed: the Debian base image is made from Debian's own packages
(``debootstrap --variant=minbase bookworm`` from the host's Debian mirror, then
``docker import``), and on it

* ``flexride`` (API and workers) from the ``Dockerfile``, its Python packages from PyPI
  (``requirements.lock``),
* ``flexride-redis`` and ``flexride-postgres`` from Debian's packages (``docker/redis``,
  ``docker/postgres``), stand-ins for the official ``redis`` and ``postgres`` images.

Each image is tagged ``<name>:in-<key>``, where the key is a digest of everything it is built
from (its Dockerfile and build context, the base image, the build arguments), and
``<name>:latest``; an image whose key is already present is not built again. The builds reach
the package registries as the host does: its apt mirror, and pip's index URLs, trusted hosts
and extra CA certificates (``pip config``, ``PIP_*`` variables), given as build arguments of
the build stage only. The build time and size of every image is printed (and written as JSON
with ``--json``). Run as root (debootstrap) with a Docker engine at ``DOCKER_HOST``::

    python3 tools/docker_images.py --env-file .env   # then: docker compose up -d
    python3 tools/docker_images.py --hub              # base debian:bookworm-slim from a registry
"""

from __future__ import annotations

import argparse
import hashlib
import inspect
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import asdict, dataclass
from datetime import UTC, datetime
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SUITE = "bookworm"
HUB_BASE = "debian:bookworm-slim"
#: What the flexride image is built from (the allowlist of .dockerignore)
FLEXRIDE_INPUTS = ("Dockerfile", "requirements.lock", "pyproject.toml", "README.md", "backend",
                   "frontend", "docker/entrypoint.py", "docker/healthcheck.py")
#: Image repository, build context and the compose variable that selects it
IMAGES = {
    "flexride": ("flexride", ROOT, "FLEXRIDE_IMAGE"),
    "redis": ("flexride-redis", ROOT / "docker" / "redis", "FLEXRIDE_REDIS_IMAGE"),
    "postgres": ("flexride-postgres", ROOT / "docker" / "postgres", "FLEXRIDE_POSTGRES_IMAGE"),
}
_SKIP = re.compile(r"(^|/)(__pycache__|[^/]*\.egg-info)(/|$)|\.pyc$")
_DEFAULT_MIRRORS = ("http://deb.debian.org/debian", "http://deb.debian.org/debian-security")


@dataclass
class Built:
    """One image: its tag, the seconds its build took (0 when it was already there), size."""

    name: str
    tag: str
    build_s: float
    size_mb: float


def docker(*args: str, **kwargs: object) -> str:
    """Run ``docker ARGS`` (the engine of ``DOCKER_HOST``); return its standard output."""
    r = subprocess.run(["docker", *args], text=True, capture_output=True,
                       **kwargs)  # type: ignore[call-overload]
    if r.returncode != 0:
        said = (r.stderr or "").strip().splitlines()[-5:]
        raise SystemExit(f"docker_images: `docker {args[0]}` failed (exit {r.returncode})"
                         + (": " + " | ".join(said) if said else ""))
    return r.stdout or ""


def image_id(ref: str) -> str | None:
    """The id of image ``ref``, or None when the engine has no such image."""
    r = subprocess.run(["docker", "image", "inspect", "--format", "{{.Id}}", ref],
                       capture_output=True, text=True)
    return r.stdout.strip() if r.returncode == 0 else None


def _files(root: Path, names: Iterable[str]) -> list[Path]:
    out: list[Path] = []
    for name in names:
        p = root / name
        out += sorted(f for f in p.rglob("*") if f.is_file()) if p.is_dir() else [p]
    return [f for f in out if not _SKIP.search(f.relative_to(root).as_posix())]


def digest(root: Path, names: Iterable[str], *extra: str) -> str:
    """SHA-256 of the files ``names`` under ``root`` (directories recursively: paths, modes
    and contents, caches left out) and of the strings ``extra``."""
    h = hashlib.sha256()
    for f in _files(root, names):
        h.update(f"{f.relative_to(root).as_posix()}\0{f.stat().st_mode & 0o111}\0".encode())
        h.update(f.read_bytes())
    for s in extra:
        h.update(b"\0" + s.encode())
    return h.hexdigest()


# -- the host's package sources ------------------------------------------------------------

def _apt_entries() -> list[tuple[str, str]]:
    """``(uri, suite)`` of the host's deb sources (one-line and deb822 formats)."""
    apt = Path("/etc/apt")
    entries: list[tuple[str, str]] = []
    for f in [apt / "sources.list", *sorted((apt / "sources.list.d").glob("*.list"))]:
        for line in f.read_text().splitlines() if f.is_file() else []:
            m = re.match(r"\s*deb\s+(?:\[[^]]*\]\s+)?(\S+)\s+(\S+)", line)
            entries += [(m.group(1), m.group(2))] if m else []
    for f in sorted((apt / "sources.list.d").glob("*.sources")):
        for stanza in re.split(r"\n\s*\n", f.read_text()):
            fields = dict(re.findall(r"^(\w[\w-]*):\s*(.*)$", stanza, re.M))
            if "deb" in fields.get("Types", "").split() and fields.get("Enabled") != "no":
                entries += [(u, s) for u in fields.get("URIs", "").split()
                            for s in fields.get("Suites", "").split()]
    return entries


def debian_mirrors() -> tuple[str, str]:
    """The host's Debian mirror and security mirror for ``bookworm`` (deb.debian.org else)."""
    entries = _apt_entries()
    main = next((u for u, s in entries if s == SUITE), _DEFAULT_MIRRORS[0])
    security = next((u for u, s in entries if s == f"{SUITE}-security"), _DEFAULT_MIRRORS[1])
    return main.rstrip("/"), security.rstrip("/")


def _pip_config() -> dict[str, str]:
    """pip's settings on this host (``pip config list`` and ``PIP_*`` variables)."""
    out = subprocess.run([sys.executable, "-m", "pip", "config", "list"],
                         capture_output=True, text=True).stdout
    conf = {k.split(".", 1)[1]: v for k, v in re.findall(r"^([\w.-]+)='(.*)'$", out, re.M)}
    for key in ("index-url", "extra-index-url", "trusted-host", "cert", "timeout"):
        env = os.environ.get("PIP_" + key.replace("-", "_").upper())
        conf[key] = env if env else conf.get(key, "")
    conf["timeout"] = os.environ.get("PIP_DEFAULT_TIMEOUT") or conf["timeout"]
    return conf


def _extra_ca_pem(cert: str) -> str:
    """The CA certificates a build needs beyond Debian's: the host's local ones
    (/usr/local/share/ca-certificates) when pip uses the system bundle, else pip's file."""
    system = {"/etc/ssl/certs/ca-certificates.crt", ""}
    if cert and cert not in system and Path(cert).is_file():
        return Path(cert).read_text()
    local = sorted(Path("/usr/local/share/ca-certificates").rglob("*.crt"))
    return "".join(f.read_text() for f in local)


def pip_build_args() -> dict[str, str]:
    """Build arguments that let pip in a build reach the index the way the host's pip does.

    Returns
    -------
    dict
        ``PIP_INDEX_URL``, ``PIP_EXTRA_INDEX_URL``, ``PIP_TRUSTED_HOST`` (only network URLs:
        the host's ``file://`` indexes are not in the build), ``PIP_DEFAULT_TIMEOUT`` and
        ``EXTRA_CA_CERTS``; unset ones left out.
    """
    conf = _pip_config()
    urls = {k: " ".join(u for u in conf[k].split() if u.startswith(("http://", "https://")))
            for k in ("index-url", "extra-index-url")}
    args = {"PIP_INDEX_URL": urls["index-url"], "PIP_EXTRA_INDEX_URL": urls["extra-index-url"],
            "PIP_TRUSTED_HOST": conf["trusted-host"], "PIP_DEFAULT_TIMEOUT": conf["timeout"],
            "EXTRA_CA_CERTS": _extra_ca_pem(conf["cert"])}
    for proxy in ("http_proxy", "https_proxy", "no_proxy"):
        args[proxy] = os.environ.get(proxy) or os.environ.get(proxy.upper(), "")
    return {k: v for k, v in args.items() if v}


# -- the Debian base ----------------------------------------------------------------------

def _tidy_rootfs(root: Path, mirrors: tuple[str, str]) -> None:
    """Make a debootstrap tree a container base like debian:bookworm-slim: sources of all
    three suites, no recommends, no documentation, no services started by packages, no apt
    cache or lists."""
    main, security = mirrors
    (root / "etc/apt/sources.list").write_text(
        f"deb {main} {SUITE} main\ndeb {main} {SUITE}-updates main\n"
        f"deb {security} {SUITE}-security main\n")
    (root / "etc/apt/apt.conf.d/docker-slim").write_text(
        'APT::Install-Recommends "false";\nAPT::Install-Suggests "false";\n'
        'Acquire::Languages "none";\n'
        'DPkg::Post-Invoke { "rm -f /var/cache/apt/archives/*.deb || true"; };\n')
    (root / "etc/dpkg/dpkg.cfg.d/docker-slim").write_text(
        "path-exclude /usr/share/doc/*\npath-include /usr/share/doc/*/copyright\n"
        "path-exclude /usr/share/man/*\npath-exclude /usr/share/info/*\n"
        "path-exclude /usr/share/locale/*\npath-include /usr/share/locale/locale.alias\n")
    policy = root / "usr/sbin/policy-rc.d"
    policy.write_text("#!/bin/sh\n# no services start while images are built\nexit 101\n")
    policy.chmod(0o755)
    for pattern in ("var/cache/apt/archives/*.deb", "var/cache/apt/*.bin", "var/lib/apt/lists/*",
                    "var/log/*.log", "var/log/apt/*", "usr/share/man/*", "usr/share/info/*"):
        for p in root.glob(pattern):
            shutil.rmtree(p) if p.is_dir() and not p.is_symlink() else p.unlink()
    for p in (root / "usr/share/doc").glob("*/*"):
        if p.name != "copyright":
            shutil.rmtree(p) if p.is_dir() and not p.is_symlink() else p.unlink()


def _debootstrap(root: Path, mirror: str) -> None:
    if shutil.which("debootstrap") is None:
        raise SystemExit("docker_images: debootstrap is missing (apt-get install debootstrap)")
    r = subprocess.run(["debootstrap", "--variant=minbase", SUITE, str(root), mirror],
                       capture_output=True, text=True)
    if r.returncode != 0:
        tail = (r.stdout + r.stderr).strip().splitlines()[-3:]
        raise SystemExit(f"docker_images: debootstrap failed: {' | '.join(tail)}")


def make_base(mirrors: tuple[str, str], rebuild: bool = False) -> Built:
    """The local Debian base ``flexride-base:bookworm``, made with debootstrap unless an
    image of the same recipe and mirrors exists.

    Parameters
    ----------
    mirrors : (str, str)
        Debian mirror and security mirror (:func:`debian_mirrors`).
    rebuild : bool
        Make it again even when present (e.g. for Debian's latest updates).
    """
    recipe = inspect.getsource(_tidy_rootfs) + inspect.getsource(_debootstrap)
    key = hashlib.sha256("\0".join([recipe, SUITE, *mirrors]).encode()).hexdigest()[:16]
    tag = f"flexride-base:{SUITE}-{key}"
    start, made = time.monotonic(), rebuild or image_id(tag) is None
    if made:
        print(f"making the Debian base {tag} with debootstrap from {mirrors[0]}", flush=True)
        with tempfile.TemporaryDirectory(prefix="flexride-rootfs-") as tmp:
            root = Path(tmp) / "rootfs"
            _debootstrap(root, mirrors[0])
            _tidy_rootfs(root, mirrors)
            _import(root, tag)
    seconds = time.monotonic() - start if made else 0.0
    docker("tag", tag, f"flexride-base:{SUITE}")
    return Built("base", tag, seconds, image_size_mb(tag))


def _import(root: Path, tag: str) -> None:
    """``docker import`` the tree ``root`` as image ``tag``."""
    tar = subprocess.Popen(["tar", "-C", str(root), "--numeric-owner", "-c", "."],
                           stdout=subprocess.PIPE)
    docker("import", "--change", 'CMD ["bash"]', "-", tag, stdin=tar.stdout)
    if tar.wait() != 0:
        raise SystemExit("docker_images: tar of the debootstrap tree failed")


def image_size_mb(ref: str) -> float:
    """Size of image ``ref`` in MB (10^6 bytes), as ``docker images`` shows it."""
    return int(docker("image", "inspect", "--format", "{{.Size}}", ref)) / 1e6


# -- the images ----------------------------------------------------------------------------

def _build_env() -> dict[str, str]:
    """The environment of ``docker build``: the classic builder when buildx is missing (the
    Dockerfiles use no BuildKit-only syntax)."""
    env = dict(os.environ)
    has_buildx = subprocess.run(["docker", "buildx", "version"], capture_output=True,
                                env=env).returncode == 0
    if not has_buildx:
        env.setdefault("DOCKER_BUILDKIT", "0")
    return env


def build_image(name: str, base: str, args: dict[str, str], network: str,
                rebuild: bool = False) -> Built:
    """Build image ``name`` (a key of :data:`IMAGES`) on ``base`` unless it is up to date.

    Parameters
    ----------
    name : str
        ``flexride``, ``redis`` or ``postgres``.
    base : str
        The base image (``flexride-base:bookworm-…`` or ``debian:bookworm-slim``).
    args : dict
        Build arguments (only the flexride image takes pip's).
    network : str
        Network of the build's containers (``host``: the host's own way to the registries).
    rebuild : bool
        Build even when an image of the same key exists.
    """
    repo, context, _ = IMAGES[name]
    inputs = (*FLEXRIDE_INPUTS, ".dockerignore") if name == "flexride" else ("",)
    base_id = image_id(base) or base
    key = digest(context, inputs, base_id, json.dumps(args, sort_keys=True))[:16]
    tag = f"{repo}:in-{key}"
    start = time.monotonic()
    if rebuild or image_id(tag) is None:
        flags = [f"--build-arg=BASE_IMAGE={base}", f"--network={network}",
                 f"--label=org.flexride.inputs={key}", "--pull=false", "--rm", "--force-rm"]
        flags += [f"--build-arg={k}={v}" for k, v in sorted(args.items())]
        _logged_build([*flags, "-t", tag, str(context)], tag)
        seconds = time.monotonic() - start
    else:
        seconds = 0.0
    docker("tag", tag, f"{repo}:latest")
    _untag_older(repo, tag)
    return Built(name, tag, seconds, image_size_mb(tag))


def _logged_build(args: list[str], tag: str) -> None:
    """``docker build ARGS``, its output in a log file (builds run side by side) that is
    named when the build starts and quoted when it fails."""
    log = Path(tempfile.gettempdir()) / f"flexride-build-{tag.replace(':', '-')}.log"
    print(f"building {tag} (log: {log})", flush=True)
    with log.open("w") as out:
        r = subprocess.run(["docker", "build", *args], stdout=out, stderr=subprocess.STDOUT,
                           env=_build_env())
    if r.returncode != 0:
        tail = log.read_text(errors="replace").strip().splitlines()[-15:]
        raise SystemExit(f"docker_images: building {tag} failed (exit {r.returncode}), "
                         f"end of {log}:\n" + "\n".join(tail))


def _untag_older(repo: str, keep: str, min_age_s: float = 6 * 3600.0) -> None:
    """Remove the ``in-…`` tags of ``repo`` other than ``keep`` made more than ``min_age_s``
    ago (their layers go too; a younger one may be another run's on this engine)."""
    tags = docker("images", repo, "--format", "{{.Repository}}:{{.Tag}}").split()
    old = [t for t in tags if t != keep and t.split(":", 1)[1].startswith("in-")]
    now = datetime.now(UTC)
    for tag in old:
        created = docker("image", "inspect", "--format", "{{.Created}}", tag).strip()
        made = datetime.strptime(created[:19], "%Y-%m-%dT%H:%M:%S").replace(tzinfo=UTC)
        if (now - made).total_seconds() > min_age_s:
            subprocess.run(["docker", "rmi", tag], capture_output=True)


def build_all(hub: bool = False, network: str = "host", rebuild: bool = False) -> list[Built]:
    """The base (unless ``hub``) and the three images; see :func:`build_image`."""
    built = []
    if hub:
        base = HUB_BASE
    else:
        built.append(make_base(debian_mirrors(), rebuild))
        base = built[0].tag
    pip_args = pip_build_args()
    # flexride (pip, then numba's compiler: mostly one core) beside Redis and PostgreSQL
    # (apt): side by side on two cores
    with ThreadPoolExecutor(max_workers=2) as pool:
        app = pool.submit(build_image, "flexride", base, pip_args, network, rebuild)
        services = pool.submit(lambda: [build_image(name, base, {}, network, rebuild)
                                        for name in ("redis", "postgres")])
        built += [app.result(), *services.result()]
    return built


def compose_env(built: Iterable[Built]) -> dict[str, str]:
    """The variables of docker-compose.yml that select the images in ``built``."""
    return {IMAGES[b.name][2]: b.tag for b in built if b.name in IMAGES}


def report(built: list[Built]) -> str:
    """The measured figures as a small table."""
    lines = [f"{'image':<40} {'build s':>8} {'size MB':>8}"]
    lines += [f"{b.tag:<40} {b.build_s:>8.1f} {b.size_mb:>8.1f}" for b in built]
    lines.append(f"{'total':<40} {sum(b.build_s for b in built):>8.1f} "
                 f"{sum(b.size_mb for b in built if b.name != 'base'):>8.1f}")
    return "\n".join(lines)


def main(argv: list[str]) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--hub", action="store_true",
                   help=f"build on {HUB_BASE} from a registry instead of a debootstrap base")
    p.add_argument("--network", default="host", help="network of the build (default host)")
    p.add_argument("--rebuild", action="store_true", help="build even what is up to date")
    p.add_argument("--env-file", type=Path, help="write the compose variables to this file")
    p.add_argument("--json", type=Path, help="write the figures to this file")
    opts = p.parse_args(argv)
    built = build_all(opts.hub, opts.network, opts.rebuild)
    print(report(built))
    env = compose_env(built)
    if opts.env_file:
        opts.env_file.write_text("".join(f"{k}={v}\n" for k, v in env.items()))
    if opts.json:
        opts.json.write_text(json.dumps([asdict(b) for b in built], indent=1) + "\n")
    print(" ".join(f"{k}={v}" for k, v in env.items()) + " docker compose up -d")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
