"""The package's TypedDicts describe the dicts it returns: the same keys, and for a
render's outputs the dtypes numpy gives. (mypy --strict checks the annotations
themselves; these tests check that they tell the truth.)"""

import json
import typing

import numpy as np
import numpy.typing

import chiaro
import chiaro.ray
import scenes


def hints(cls):
    """A TypedDict's fields (its bases' too) and their types. The package writes the types
    as text naming numpy.typing.NDArray, which it does not import at run time (`import
    chiaro` does not import numpy): they are evaluated with numpy's names given."""
    return typing.get_type_hints(cls, localns={"np": np, "NDArray": numpy.typing.NDArray})


def test_every_exported_name_exists():
    for module in (chiaro, chiaro.ray):
        assert all(hasattr(module, name) for name in module.__all__), module.__name__


def test_render_outputs_names_every_output_with_its_dtype(renderer, scene):
    fields = hints(chiaro.RenderOutputs)
    assert set(fields) == set(chiaro.OUTPUTS) | {"shadow_lights"}
    assert chiaro.RenderOutputs.__total__ is False

    out = renderer.render(scene, camera="overview", width=32, height=24, outputs=chiaro.OUTPUTS)
    assert set(out) == set(fields)
    for name in chiaro.OUTPUTS:
        # NDArray[X] is ndarray[shape, dtype[X]].
        (scalar,) = typing.get_args(typing.get_args(fields[name])[-1])
        assert out[name].dtype == np.dtype(scalar), name
    assert fields["shadow_lights"] == typing.List[int] and out["shadow_lights"] == [scenes.SUN_NODE]


def test_the_other_dicts_have_the_keys_their_types_name(renderer, scene, scene_path, tmp_path):
    assert [set(d) for d in chiaro.devices()] == [set(hints(chiaro.DeviceInfo))] * len(chiaro.devices())
    assert set(renderer.device) == set(hints(chiaro.RendererDevice))
    (row,) = chiaro.compare(scene, camera="overview", width=32, height=24, renderer=renderer)
    assert set(row) == set(hints(chiaro.LightComparison))
    summary = chiaro.render_jobs([{"id": "a", "scene": scene_path, "width": 16, "height": 16}], tmp_path / "jobs",
                                 renderer=renderer)
    assert set(summary) == set(hints(chiaro.JobsSummary)) and summary["done"] == 1

    # An empty list returns its summary before Ray is started (or needed).
    assert set(chiaro.ray.render_dataset([], tmp_path / "ray")) == set(hints(chiaro.ray.DatasetSummary))
    stage = chiaro.ray.ChiaroRenderStage(output=str(tmp_path / "stage"), device=renderer.device["index"])
    statuses = stage({"job": np.array([json.dumps({"id": "lost", "scene": str(tmp_path / "no.gltf")})],
                                      dtype=object)})
    assert set(statuses) == set(hints(chiaro.ray.StageStatuses))
    assert list(statuses["status"]) == ["failed"]
