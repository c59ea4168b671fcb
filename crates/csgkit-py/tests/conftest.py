"""Fixtures: the shared data folder, the csgkit command-line binary, simple solids as arrays.

The shared data folder is ``../shared/data`` beside the repository (or
``$CSGKIT_SHARED_DATA``); tests that need it skip, saying so, when it is absent.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[3]


def shared_data_dir() -> Path:
    return Path(os.environ.get("CSGKIT_SHARED_DATA", REPO.parent / "shared" / "data"))


@pytest.fixture(scope="session")
def shared_data() -> Path:
    folder = shared_data_dir()
    if not (folder / "meshes").is_dir():
        pytest.skip(f"shared data folder {folder} is absent")
    return folder


@pytest.fixture(scope="session")
def manifest(shared_data: Path) -> dict:
    entries = json.loads((shared_data / "manifest.json").read_text())["meshes"]
    return {Path(e["file"]).name: e for e in entries}


@pytest.fixture(scope="session")
def cli() -> Path:
    """The release `csgkit` binary of this checkout ($CSGKIT_BIN, else the target folder),
    built with cargo when it is missing."""
    if "CSGKIT_BIN" in os.environ:
        return Path(os.environ["CSGKIT_BIN"])
    target = Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
    binary = target / "release" / "csgkit"
    if not binary.exists():
        cargo = shutil.which("cargo")
        if cargo is None:
            pytest.skip("no csgkit binary and no cargo to build it")
        subprocess.run([cargo, "build", "--release", "-p", "csgkit-cli"], cwd=REPO, check=True)
    return binary


def cube(lo=(0.0, 0.0, 0.0), hi=(1.0, 1.0, 1.0)):
    """An axis-aligned box as (vertices, triangles), outward."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    v = np.array([[(hi if (k >> a) & 1 else lo)[a] for a in range(3)] for k in range(8)])
    f = np.array([[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
                  [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5]])
    return v, f


def sphere(center=(0.0, 0.0, 0.0), radius=1.0, subdivisions=3):
    """An icosphere (trimesh's) as (vertices, faces)."""
    import trimesh

    s = trimesh.creation.icosphere(subdivisions=subdivisions, radius=radius)
    return np.asarray(s.vertices) + np.asarray(center, float), np.asarray(s.faces)
