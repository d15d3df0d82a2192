"""chiaro.compare: the ray-traced reference agrees with the sun's shadow of the box."""

import chiaro


def test_compare_reports_each_light_as_the_cli_does(renderer, scene):
    (row,) = chiaro.compare(scene, camera="overview", width=128, height=96, renderer=renderer)
    assert row["node"] == 2 and row["light"] == "sun" and row["kind"] == "directional"
    assert row["not_compared"] is None and row["compared"] > 5000
    assert 0.0 <= row["disagree_percent"] <= 0.5
    assert row["disagree_percent"] == row["false_percent"] + row["missed_percent"] or abs(
        row["disagree_percent"] - row["false_percent"] - row["missed_percent"]) < 1e-9


def test_a_light_without_shadows_is_not_compared(renderer, scene):
    scene.lights[0].shadows = False
    (row,) = renderer.compare(scene, camera="overview", width=64, height=48)
    assert row["not_compared"] == "casts no shadows" and row["disagree_percent"] is None
