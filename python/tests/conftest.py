import os
import sys

import pytest

sys.path.insert(0, os.path.dirname(__file__))

import chiaro  # noqa: E402
import scenes  # noqa: E402


@pytest.fixture(scope="session")
def renderer():
    """One renderer for the session, on the CPU device where there is one (CI's lavapipe)."""
    return chiaro.Renderer(device=os.environ.get("CHIARO_TEST_DEVICE", "auto"))


@pytest.fixture(scope="session")
def scene_path(tmp_path_factory):
    return scenes.write_scene(str(tmp_path_factory.mktemp("scene") / "box.gltf"))


@pytest.fixture()
def scene(scene_path):
    return chiaro.load(scene_path)
