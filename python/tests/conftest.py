"""Common fixtures: the repository, its test meshes (`data/meshes`) and the `rocking` CLI."""

from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path
from typing import List

import pytest

REPO = Path(__file__).resolve().parents[2]
# The real test meshes bundled with the repository (see data/README.md).
MESH_DIR = REPO / "data" / "meshes"


def rocking_binary() -> Path | None:
    """The CLI: `$ROCKING_BIN` (set by .ci/run), else the newest of target/{release,debug}/rocking."""
    env = os.environ.get("ROCKING_BIN")
    if env:
        return Path(env)
    found = [REPO / "target" / p / "rocking" for p in ("release", "debug")]
    found = [p for p in found if p.exists()]
    return max(found, key=lambda p: p.stat().st_mtime) if found else None


class Cli:
    def __init__(self, path: Path):
        self.path = path

    def run(self, args: List[str], check: bool = True) -> subprocess.CompletedProcess:
        r = subprocess.run([str(self.path), *args], capture_output=True, text=True)
        if check and r.returncode != 0:
            raise AssertionError(f"{self.path} {' '.join(args)} failed: {r.stderr}")
        return r

    def json(self, args: List[str]) -> dict:
        return json.loads(self.run([*args, "--json"]).stdout)

    def error(self, args: List[str]) -> str:
        """The message after `error: ` of a failing command."""
        r = self.run(args, check=False)
        assert r.returncode != 0, f"{args} should fail"
        line = r.stderr.strip().splitlines()[-1]
        assert line.startswith("error: "), r.stderr
        return line[len("error: "):]


@pytest.fixture(scope="session")
def cli() -> Cli:
    path = rocking_binary()
    if os.environ.get("ROCKING_BIN") and not path.exists():
        pytest.fail(f"ROCKING_BIN={path} does not exist")
    if path is None or not path.exists():
        pytest.skip("the rocking CLI is not built (cargo build --bin rocking, or set ROCKING_BIN)")
    return Cli(path)


def mesh(name: str) -> Path:
    """The path of a mesh of `data/meshes`; it must be there."""
    p = MESH_DIR / name
    assert p.exists(), f"{p} is missing from the repository"
    return p
