"""The service image's lock file satisfies the dependencies of pyproject.toml."""

from __future__ import annotations

import tomllib
from pathlib import Path

from packaging.requirements import Requirement
from packaging.utils import canonicalize_name

ROOT = Path(__file__).resolve().parents[2]


def _locked() -> dict[str, str]:
    out = {}
    for line in (ROOT / "requirements.lock").read_text().splitlines():
        if line and not line.startswith("#"):
            name, version = line.split("==")
            out[canonicalize_name(name)] = version
    return out


def test_lock_pins_every_dependency_within_its_range():
    deps = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["dependencies"]
    locked = _locked()
    for dep in map(Requirement, deps):
        name = canonicalize_name(dep.name)
        assert name in locked, f"{dep.name} is not in requirements.lock (run tools/lock_image.py)"
        assert dep.specifier.contains(locked[name], prereleases=True), (dep, locked[name])


def test_dockerfile_installs_the_lock_then_the_package_without_dependencies():
    text = (ROOT / "Dockerfile").read_text()
    assert text.index("pip install -r requirements.lock") < text.index("pip install --no-deps .")
