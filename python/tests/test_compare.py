"""chiaro.compare: the ray-traced reference agrees with the sun's shadow of the box."""

import chiaro


def test_compare_reports_each_light_as_the_cli_does(renderer, scene):
    (row,) = chiaro.compare(scene, camera="overview", width=128, height=96, renderer=renderer)
    assert row["node"] == 2 and row["light"] == "sun" and row["kind"] == "directional"
    assert row["not_compared"] is None and row["compared"] > 5000
    assert 0.0 <= row["disagree_percent"] <= 0.5
    assert row["disagree_percent"] == row["false_percent"] + row["missed_percent"] or abs(
        row["disagree_percent"] - row["false_percent"] - row["missed_percent"]) < 1e-9


def test_edge_band_narrows_what_is_left_out_beside_traced_edges(renderer, scene):
    compared = [renderer.compare(scene, camera="overview", width=96, height=72, edge_band=band)[0]["compared"]
                for band in (3, 1, 0)]
    assert compared[0] < compared[1] < compared[2], compared
    (default,) = renderer.compare(scene, camera="overview", width=96, height=72)
    assert default["compared"] == compared[0]
    for bad in (-1, 65):
        try:
            chiaro.compare(scene, camera="overview", width=32, height=24, renderer=renderer, edge_band=bad)
        except ValueError as e:
            assert "edge_band" in str(e)
        else:
            raise AssertionError("edge_band %d was taken" % bad)


def test_a_light_without_shadows_is_not_compared(renderer, scene):
    scene.lights[0].shadows = False
    (row,) = renderer.compare(scene, camera="overview", width=64, height=48)
    assert row["not_compared"] == "casts no shadows" and row["disagree_percent"] is None


def test_a_pcss_light_reports_its_visibility_against_the_traced_disc(renderer, scene):
    (hard,) = renderer.compare(scene, camera="overview", width=96, height=72)
    assert hard["visibility_mean_abs"] is None
    sun = scene.lights[0]
    sun.shadows = "pcss"
    sun.angular_diameter = 3.0
    assert sun.shadow_mode == "pcss" and sun.angular_diameter == 3.0
    (row,) = renderer.compare(scene, camera="overview", width=96, height=72)
    assert row["not_compared"] is None and row["compared"] > 2000
    assert 0.0 <= row["visibility_mean_abs"] < 0.03
    assert row["visibility_mean_abs"] <= row["visibility_p95_abs"] or row["visibility_p95_abs"] == 0.0
    assert 0.0 <= row["visibility_far_off_percent"] < 10.0
    assert hard["penumbra_mean_abs"] is None
    assert 0.0 <= row["penumbra_mean_abs"] <= 1.0 and 0.0 <= row["penumbra_far_off_percent"] <= 100.0
