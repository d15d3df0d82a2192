"""chiaro.render_jobs: job lists rendered into one folder per job, as `chiaro batch`
renders them. Counts of done, skipped and failed jobs; a rerun that touches nothing; a
failed job's report; images equal to the renderer's own; shards that split a list once."""

import json
import os
import struct
import zlib

import numpy as np
import pytest

import chiaro
import scenes

W, H = 64, 48


def read_png(path):
    """An 8-bit RGB or RGBA, non-interlaced PNG as an (H, W, C) uint8 array (numpy and the
    standard library only: no image package in the test environment)."""
    with open(path, "rb") as f:
        data = f.read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    pos, idat, header = 8, b"", None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    width, height, depth, colour, _, _, interlace = header
    assert depth == 8 and colour in (2, 6) and interlace == 0, header
    channels = 3 if colour == 2 else 4
    raw = np.frombuffer(zlib.decompress(idat), np.uint8).reshape(height, 1 + width * channels)
    out = np.zeros((height, width * channels), np.int32)
    previous = np.zeros(width * channels, np.int32)
    for y in range(height):
        kind, line = raw[y, 0], raw[y, 1:].astype(np.int32)
        row = np.zeros_like(line)
        for x in range(len(line)):
            a = row[x - channels] if x >= channels else 0
            b = previous[x]
            c = previous[x - channels] if x >= channels else 0
            if kind == 0:
                predictor = 0
            elif kind == 1:
                predictor = a
            elif kind == 2:
                predictor = b
            elif kind == 3:
                predictor = (a + b) // 2
            else:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                predictor = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
            row[x] = (line[x] + predictor) & 0xFF
        out[y] = row
        previous = row
    return out.astype(np.uint8).reshape(height, width, channels)


def meta(output, job_id):
    with open(os.path.join(output, job_id, "meta.json")) as f:
        return json.load(f)


def test_jobs_render_skip_on_rerun_and_report_failures(renderer, scene_path, tmp_path):
    output = str(tmp_path / "out")
    jobs = [
        {"id": "overview", "scene": scene_path, "camera": "overview", "width": W, "height": H,
         "outputs": ["rgb", "depth", "instance"], "seed": 3},
        {"id": "placed", "scene": scene_path, "camera": {"eye": [4, 3, 5], "target": [0, 0.5, 0]},
         "width": W, "height": H, "outputs": ["shadow", "label"]},
        {"id": "lost", "scene": str(tmp_path / "missing.gltf")},
        {"id": "typo", "scene": scene_path, "widht": 32},
    ]
    result = chiaro.render_jobs(jobs, output, renderer=renderer)
    assert (result["done"], result["skipped"], result["failed"]) == (2, 0, 2)
    assert set(result["errors"]) == {"lost", "typo"}
    assert "missing.gltf" in result["errors"]["lost"]
    assert result["errors"]["typo"].startswith("<jobs>:4: unknown key 'widht'")
    names = sorted(os.listdir(output))
    assert names == ["lost.error.json", "overview", "placed", "typo.error.json"]
    with open(os.path.join(output, "lost.error.json")) as f:
        report = json.load(f)
    assert report["id"] == "lost" and report["line"] == 3 and report["job"] == jobs[2]
    assert report["error"] == result["errors"]["lost"]

    record = meta(output, "overview")
    assert record["job"] == jobs[0]
    assert record["seed"] == 3 and (record["width"], record["height"]) == (W, H)
    assert sorted(record["files"]) == ["depth.exr", "instance.exr", "rgb.png"]
    assert record["inputs"][0]["path"] == os.path.abspath(scene_path)
    assert len(record["scene_hash"]) == 64 and record["hash"] == "blake3"
    assert record["chiaro_version"] == chiaro.__version__
    assert record["device"]["name"] == renderer.device["name"]
    assert sorted(meta(output, "placed")["files"]) == ["label.exr", "shadow.%d.exr" % scenes.SUN_NODE]

    times = {name: os.stat(os.path.join(output, name, "rgb.png")).st_mtime_ns for name in ["overview"]}
    again = chiaro.render_jobs(jobs, output, renderer=renderer)
    assert (again["done"], again["skipped"], again["failed"]) == (0, 2, 2)
    assert os.stat(os.path.join(output, "overview", "rgb.png")).st_mtime_ns == times["overview"]


def test_a_job_image_equals_the_renderers_own(renderer, scene, scene_path, tmp_path):
    before = renderer.render(scene, camera="overview", width=W, height=H, outputs=("rgb",))["rgb"]
    jobs = [{"id": "a", "scene": scene_path, "camera": "overview", "width": W, "height": H}]
    result = chiaro.render_jobs(jobs, tmp_path / "out", renderer=renderer)
    assert result["done"] == 1, result
    png = read_png(str(tmp_path / "out" / "a" / "rgb.png"))
    assert png.shape[:2] == (H, W)
    np.testing.assert_array_equal(png[..., :3], before)
    # The renderer's own frames are unchanged after the batch used its device.
    after = renderer.render(scene, camera="overview", width=W, height=H, outputs=("rgb",))["rgb"]
    np.testing.assert_array_equal(after, before)


def test_a_jsonl_file_split_into_shards_renders_each_job_once(renderer, scene_path, tmp_path):
    path = tmp_path / "jobs.jsonl"
    lines = [json.dumps({"id": "j%d" % i, "scene": scene_path, "width": 16, "height": 16}) for i in range(5)]
    path.write_text("\n".join(lines[:2]) + "\n\n" + "\n".join(lines[2:]) + "\n")
    output = tmp_path / "out"
    first = chiaro.render_jobs(path, output, shard=(0, 2), renderer=renderer)
    second = chiaro.render_jobs(str(path), output, shard="1/2", renderer=renderer)
    assert (first["done"], second["done"]) == (3, 2)
    assert sorted(os.listdir(output)) == ["j%d" % i for i in range(5)]


def test_bad_lists_and_shards_raise_before_anything_renders(renderer, scene_path, tmp_path):
    output = tmp_path / "out"
    job = {"id": "a", "scene": scene_path}
    with pytest.raises(ValueError, match="<jobs>:2: id 'a' is already the id of line 1"):
        chiaro.render_jobs([job, job], output, renderer=renderer)
    with pytest.raises(ValueError, match=r"<jobs>:1: id \".hidden\": starts with '.'"):
        chiaro.render_jobs([{"id": ".hidden", "scene": scene_path}], output, renderer=renderer)
    with pytest.raises(ValueError, match="<jobs>:1: not JSON"):
        chiaro.render_jobs(["{broken"], output, renderer=renderer)
    with pytest.raises(ValueError, match="shard 2 of 2 does not exist"):
        chiaro.render_jobs([job], output, shard=(2, 2), renderer=renderer)
    with pytest.raises(ValueError, match="expected I/N"):
        chiaro.render_jobs([job], output, shard="half", renderer=renderer)
    with pytest.raises(TypeError, match="jobs"):
        chiaro.render_jobs(job, output, renderer=renderer)
    with pytest.raises(ValueError, match="give settings to the renderer"):
        chiaro.render_jobs([job], output, renderer=renderer, settings={"render": {"msaa": 1}})
    assert not output.exists() or os.listdir(output) == []
    blocker = tmp_path / "file"
    blocker.write_text("")
    with pytest.raises(OSError, match="cannot write the jobs' folders there"):
        chiaro.render_jobs([job], blocker, renderer=renderer)
