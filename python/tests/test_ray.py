"""chiaro.ray on a local Ray (two CPUs, started here, never a remote cluster): a job list
rendered by two workers, one of which dies on its first task, ends up rendered once per
job, file for file what `chiaro batch` (the binary CHIARO_BIN names) writes for the same
list; and the Ray Data stage reports each job's status. The death is the test's own doing
(a Ray worker setup hook): the package has no test hook."""

import json
import math
import os
import re
import struct
import subprocess

import numpy as np
import pytest

import scenes

try:
    import ray
except ImportError:
    pytest.fail('ray is not installed: pip install "chiaro[ray]" (scripts/test-python.sh installs it)',
                pytrace=False)

import chiaro.ray  # noqa: E402

DEVICE = os.environ.get("CHIARO_TEST_DEVICE", "auto")
OUTPUTS = ["rgb", "depth"]
FILES = ["depth.exr", "meta.json", "rgb.png"]


def chiaro_bin():
    """The CLI to compare with; its absence is a failure, never a skip."""
    path = os.environ.get("CHIARO_BIN")
    if not path or not os.access(path, os.X_OK):
        pytest.fail("CHIARO_BIN must name the chiaro binary (scripts/test-python.sh builds target/release/chiaro "
                    "and sets it), not %r" % (path,), pytrace=False)
    return path


def write_jobs(tmp_path):
    """16 small jobs over two scenes, sorted by scene, with every camera form: the file's
    camera by name and by index, and cameras placed around the box. Returns the .jsonl
    path and the jobs."""
    scene_a = scenes.write_scene(str(tmp_path / "a.gltf"))
    scene_b = scenes.write_scene(str(tmp_path / "b.gltf"), box_label=3, sun_lux=8.0)
    jobs = []
    for i in range(16):
        scene = scene_a if i < 8 else scene_b
        if i % 8 == 0:
            camera = "overview"
        elif i % 8 == 1:
            camera = 0
        else:
            angle = 2 * math.pi * i / 16
            camera = {"eye": [round(4 * math.cos(angle), 3), 2.5, round(4 * math.sin(angle), 3)],
                      "target": [0, 0.5, 0], "up": [0, 1, 0], "yfov_deg": 50}
        size = 128 if i % 8 == 3 else 96
        jobs.append({"id": "view-%02d" % i, "scene": scene, "camera": camera, "width": size, "height": size,
                     "outputs": OUTPUTS, "seed": i})
    path = tmp_path / "jobs.jsonl"
    path.write_text("".join(json.dumps(job) + "\n" for job in jobs))
    return str(path), jobs


def png_size(path):
    """A PNG's (width, height), from its IHDR chunk."""
    with open(path, "rb") as f:
        head = f.read(24)
    assert head[:8] == b"\x89PNG\r\n\x1a\n", path
    return struct.unpack(">II", head[16:24])


def start_local_ray(**options):
    """Starts a Ray of two CPUs in this process's machine, with `options` for ray.init."""
    assert not ray.is_initialized(), "a Ray from an earlier test is still running"
    ray.init(address="local", num_cpus=2, num_gpus=0, include_dashboard=False,
             object_store_memory=100 * 1024 * 1024, **options)


@pytest.fixture()
def local_ray():
    """A Ray of two CPUs in this process's machine, shut down after the test."""
    start_local_ray()
    try:
        yield
    finally:
        ray.shutdown()


def die_once_setup_hook(marker):
    """A worker_process_setup_hook for Ray: in each worker process, it wraps
    `chiaro.ray._Worker.render` so that the first task of the whole run creates the file
    `marker` (exclusively: only one task of all the workers can) and ends its own process
    with os._exit(1) before rendering, as a crash would; every other task renders. The hook
    is a closure, so Ray pickles it by value: the workers need not import this file."""

    def hook():
        import os

        import chiaro.ray

        render = chiaro.ray._Worker.render

        def render_or_die_once(self, jobs):
            try:
                fd = os.open(marker, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
            except FileExistsError:
                return render(self, jobs)
            os.write(fd, b"%d\n" % os.getpid())
            os.close(fd)
            os._exit(1)

        chiaro.ray._Worker.render = render_or_die_once

    return hook


@pytest.fixture()
def ray_whose_first_task_dies(tmp_path):
    """A local Ray as `local_ray`, whose first `render` task of chiaro.ray ends its worker;
    yields the file that task creates."""
    marker = tmp_path / "a-worker-died"
    start_local_ray(runtime_env={"worker_process_setup_hook": die_once_setup_hook(str(marker))})
    try:
        yield marker
    finally:
        ray.shutdown()


def test_a_dead_worker_loses_no_job_and_the_files_equal_chiaro_batch(tmp_path, ray_whose_first_task_dies):
    cli = chiaro_bin()
    jobs_path, jobs = write_jobs(tmp_path)
    ids = [job["id"] for job in jobs]
    marker = ray_whose_first_task_dies

    ray_out = tmp_path / "ray"
    summary = chiaro.ray.render_dataset(jobs_path, str(ray_out), num_workers=2, gpus_per_worker=0,
                                        jobs_per_task=2, device=DEVICE)

    assert marker.exists(), "no worker died: the test hook did not run"
    assert summary["errors"] == {}
    assert (summary["done"], summary["skipped"], summary["failed"], summary["workers"]) == (16, 0, 0, 2), summary
    # The one death was recovered once: on the restarted worker, or by another one.
    assert summary["restarts"] + summary["retried"] == 1, summary
    # Every job's folder once, and nothing else: no error report, no temporary folder.
    assert sorted(os.listdir(ray_out)) == ids

    cli_out = tmp_path / "cli"
    run = subprocess.run([cli, "batch", jobs_path, "--output", str(cli_out)], capture_output=True, text=True,
                         timeout=300)
    assert run.returncode == 0, run.stderr
    assert sorted(os.listdir(cli_out)) == ids

    for job in jobs:
        ours, theirs = ray_out / job["id"], cli_out / job["id"]
        assert sorted(os.listdir(ours)) == FILES and sorted(os.listdir(theirs)) == FILES, job["id"]
        meta = json.loads((ours / "meta.json").read_text())
        cli_meta = json.loads((theirs / "meta.json").read_text())
        assert meta["job"] == job
        assert meta["device"] == cli_meta["device"], (
            "the workers and chiaro batch rendered on different devices; choose one with CHIARO_TEST_DEVICE "
            "and WGPU_ADAPTER_NAME")
        # Everything but the wall time is the same record.
        meta.pop("seconds")
        cli_meta.pop("seconds")
        assert meta == cli_meta, job["id"]
        assert png_size(ours / "rgb.png") == (job["width"], job["height"])
        for name in ("rgb.png", "depth.exr"):
            assert (ours / name).read_bytes() == (theirs / name).read_bytes(), "%s/%s" % (job["id"], name)

    # A rerun renders nothing: every folder is current.
    again = chiaro.ray.render_dataset(jobs_path, str(ray_out), num_workers=2, gpus_per_worker=0, device=DEVICE)
    assert (again["done"], again["skipped"], again["failed"]) == (0, 16, 0), again


@pytest.mark.parametrize("jobs, message", [
    ([{"id": "a", "scene": "s.gltf"}, {"id": "a", "scene": "t.gltf"}], "jobs[1]: id 'a' is already the id of jobs[0]"),
    ([{"id": 7, "scene": "s.gltf"}], "jobs[0]: \"id\" must be a string"),
    ([{"scene": "s.gltf"}], "jobs[0]: no \"id\""),
    ([{"id": "../up", "scene": "s.gltf"}], "holds a slash"),
    ([{"id": ".hidden", "scene": "s.gltf"}], "starts with '.'"),
    ([{"id": "x.error.json", "scene": "s.gltf"}], "ends with '.error.json'"),
])
def test_ids_are_checked_before_ray_starts(tmp_path, jobs, message):
    with pytest.raises(ValueError, match=re.escape(message)):
        chiaro.ray.render_dataset(jobs, str(tmp_path / "out"), gpus_per_worker=0)
    assert not ray.is_initialized()
    assert not (tmp_path / "out").exists()


def test_a_duplicate_id_in_a_job_file_names_both_lines(tmp_path):
    path = tmp_path / "jobs.jsonl"
    path.write_text('{"id": "a", "scene": "s.gltf"}\n\n{"id": "a", "scene": "t.gltf"}\n')
    with pytest.raises(ValueError, match=r"jobs\.jsonl:3: id 'a' is already the id of .*jobs\.jsonl:1"):
        chiaro.ray.render_dataset(str(path), str(tmp_path / "out"), gpus_per_worker=0)


def test_the_ray_data_stage_reports_done_skipped_and_failed(tmp_path):
    # The stage is called as Ray Data's map_batches calls it, with a numpy batch.
    scene = scenes.write_scene(str(tmp_path / "a.gltf"))
    jobs = [{"id": "near", "scene": scene, "camera": {"eye": [2, 1.5, 2], "target": [0, 0.5, 0]},
             "width": 64, "height": 64, "outputs": OUTPUTS},
            {"id": "file-camera", "scene": scene, "camera": "overview", "width": 64, "height": 64},
            {"id": "missing", "scene": str(tmp_path / "nowhere.gltf"), "width": 64, "height": 64}]
    batch = {"job": np.array([json.dumps(job) for job in jobs], dtype=object)}
    out = tmp_path / "out"
    stage = chiaro.ray.ChiaroRenderStage(output=str(out), device=DEVICE)

    first = stage(batch)
    assert list(first["id"]) == ["near", "file-camera", "missing"]
    assert list(first["status"]) == ["done", "done", "failed"]
    assert first["error"][0] == first["error"][1] == ""
    assert "nowhere.gltf" in first["error"][2]
    assert sorted(os.listdir(out / "near")) == FILES
    assert sorted(os.listdir(out / "file-camera")) == ["meta.json", "rgb.png"]
    assert json.loads((out / "missing.error.json").read_text())["id"] == "missing"

    second = stage(batch)
    assert list(second["status"]) == ["skipped", "skipped", "failed"]


BENCH_SCENE = os.path.join(os.path.dirname(__file__), "..", "..", "tests", "assets", "chiaro-bench", "shadow-bench.gltf")


def near_light_jobs():
    """Jobs on the benchmark scene, each camera near one of its shadowed lights: the
    lights' importance (which places their shadow tiles) and coverage (which sizes them)
    change from job to job, so a renderer that carried them over would render a job
    differently after another."""
    near = [(0.8, -3.7), (-14.4, -16.6), (-17.8, -1.7), (-1.0, 0.3), (-5.9, -0.7), (-12.4, -11.7)]
    jobs = []
    for i in range(8):
        x, z = near[i % len(near)]
        jobs.append({"id": "near-%02d" % i, "scene": os.path.abspath(BENCH_SCENE), "width": 64, "height": 48,
                     "camera": {"eye": [x + 3.0 + 0.3 * i, 8.0 + i % 3, z + 4.0], "target": [x, 0.0, z]},
                     "outputs": ["rgb", "hdr", "shadow"]})
    return jobs


def job_files(out):
    """Every file of every job folder under `out` but meta.json (it holds the wall time)."""
    files = {}
    for job in sorted(os.listdir(out)):
        for name in sorted(os.listdir(out / job)):
            if name != "meta.json":
                files[job + "/" + name] = (out / job / name).read_bytes()
    return files


def test_a_job_renders_the_same_bytes_in_any_order_and_front_end(tmp_path, local_ray):
    jobs = near_light_jobs()
    listed = tmp_path / "jobs.jsonl"
    listed.write_text("".join(json.dumps(job) + "\n" for job in jobs))
    cli_out = tmp_path / "cli"
    run = subprocess.run([chiaro_bin(), "batch", str(listed), "--output", str(cli_out)], capture_output=True,
                         text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    expected = job_files(cli_out)
    assert len(expected) >= 3 * len(jobs)

    # Python, the list reversed, on one renderer that rendered another scene first.
    renderer = chiaro.Renderer(device=DEVICE)
    first = chiaro.render_jobs([{"id": "before", "scene": scenes.write_scene(str(tmp_path / "a.gltf"))}],
                               tmp_path / "before", renderer=renderer)
    assert first["done"] == 1, first
    python_out = tmp_path / "python"
    result = chiaro.render_jobs(list(reversed(jobs)), python_out, renderer=renderer)
    assert (result["done"], result["failed"]) == (len(jobs), 0), result
    # Ray: two workers, each taking jobs as it becomes idle.
    ray_out = tmp_path / "ray"
    summary = chiaro.ray.render_dataset(jobs[3:] + jobs[:3], str(ray_out), num_workers=2, gpus_per_worker=0,
                                        jobs_per_task=3, device=DEVICE)
    assert summary["errors"] == {} and summary["done"] == len(jobs), summary

    for name, out in (("chiaro.render_jobs, reversed", python_out), ("chiaro.ray", ray_out)):
        got = job_files(out)
        assert sorted(got) == sorted(expected), name
        differing = [f for f in expected if got[f] != expected[f]]
        assert not differing, "%s: %d files differ from chiaro batch's: %s" % (name, len(differing), differing)
