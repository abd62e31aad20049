"""Shared fixtures: the repository, ../shared beside it and the `glview` binary of the same
build (scripts/test.sh builds it before pytest runs)."""
import os
import pathlib
import subprocess

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def shared() -> pathlib.Path:
    p = REPO.parent / "shared"
    assert (p / "MANIFEST.md").exists(), f"../shared is missing beside {REPO}"
    return p


@pytest.fixture(scope="session")
def bunny(shared) -> pathlib.Path:
    return shared / "models" / "bunny-small" / "bunny.obj"


@pytest.fixture(scope="session")
def glview_bin() -> str:
    exe = os.environ.get("GLVIEW_BIN") or str(REPO / "target" / "debug" / "glview")
    assert os.path.exists(exe), f"{exe} is missing: build glview first (cargo build)"
    return exe


@pytest.fixture(scope="session")
def cli(glview_bin):
    def run(*args: str, check: bool = True) -> subprocess.CompletedProcess:
        p = subprocess.run([glview_bin, *map(str, args)], capture_output=True, text=True)
        if check:
            assert p.returncode == 0, p.stderr
        return p

    return run
