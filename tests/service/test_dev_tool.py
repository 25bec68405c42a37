"""The README's test command prepares the machine, or says in one line what it cannot get."""

from __future__ import annotations

import importlib.util
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def _dev():
    spec = importlib.util.spec_from_file_location("flexride_dev_tool", ROOT / "tools" / "dev.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_missing_packages_without_apt_give_one_line(monkeypatch):
    dev = _dev()
    monkeypatch.setattr(dev.shutil, "which", lambda name: None)
    calls = []
    monkeypatch.setattr(dev.subprocess, "call", lambda cmd, **kw: calls.append(cmd) or 100)
    problem = dev.prepare_test_machine()
    assert problem is not None and "\n" not in problem
    for pkg in ("chromium", "firefox-esr", "xvfb", "docker-compose"):
        assert pkg in problem
    assert any("apt-get" in " ".join(c) for c in calls)  # it tried to install them


def test_this_machine_is_ready():
    """On a machine set up by the test command (CI), nothing is missing."""
    dev = _dev()
    assert dev._missing_packages() == []
    assert subprocess.call(["bash", str(ROOT / "tools" / "ensure_services.sh")]) == 0
