# SPDX-License-Identifier: Apache-2.0
"""Paths for the pytest suite (ctest sets them; defaults for a run from the source tree)."""
import os
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def paths():
    return {
        "data": pathlib.Path(os.environ.get("SF_DATA_DIR", ROOT / "data")),
        "shared": pathlib.Path(os.environ.get("SF_SHARED_MESHES", ROOT.parent / "shared" / "meshes")),
        "cli": os.environ.get("SF_CLI", str(ROOT / "build" / "tools" / "smoothforce")),
    }


@pytest.fixture(scope="session")
def spot(paths):
    return str(paths["data"] / "spot_control_mesh.obj")
