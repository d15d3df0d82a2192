#!/usr/bin/env python3
"""Jobs per minute of one job list, rendered by `chiaro batch` (one process) and by
`chiaro.ray.render_dataset` (Ray workers on this machine), in one run.

The list: JOBS jobs of the animated spot-light scene in tests/assets (ShadowsSpot), each
a camera on a circle around it at its own time of the animation (so every job poses and
uploads the scene again), WIDTH x HEIGHT, outputs rgb and depth. Each way renders into a
fresh folder; the wall time includes starting the process or the Ray workers (their
devices and pipelines), not starting Ray itself. Prints a table (Markdown) and the
ratio; then checks both ways wrote the same files.

usage: jobs_throughput.py CHIARO_BIN [--jobs 48 --width 640 --height 480 --workers 2
       --out DIR]
"""

import argparse
import filecmp
import json
import math
import os
import subprocess
import sys
import tempfile
import time

import ray

import chiaro.ray

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCENE = os.path.join(REPO, "tests", "assets", "ShadowsSpot", "glTF", "shadows-spot.gltf")


def write_jobs(path, count, width, height):
    duration = chiaro.load(SCENE).duration or 0.0
    with open(path, "w") as f:
        for i in range(count):
            angle = 2 * math.pi * i / count
            eye = [round(9 * math.cos(angle), 4), 5.0, round(9 * math.sin(angle), 4)]
            job = {"id": "frame-%04d" % i, "scene": SCENE, "camera": {"eye": eye, "target": [0, 0.5, 0]},
                   "time": round(duration * i / count, 4), "width": width, "height": height,
                   "outputs": ["rgb", "depth"], "seed": i}
            f.write(json.dumps(job) + "\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("chiaro_bin")
    parser.add_argument("--jobs", type=int, default=48)
    parser.add_argument("--width", type=int, default=640)
    parser.add_argument("--height", type=int, default=480)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--out", default=None)
    args = parser.parse_args()
    out = args.out or tempfile.mkdtemp(prefix="chiaro-jobs-bench-")
    os.makedirs(out, exist_ok=True)
    jobs = os.path.join(out, "jobs.jsonl")
    write_jobs(jobs, args.jobs, args.width, args.height)

    start = time.perf_counter()
    subprocess.run([args.chiaro_bin, "batch", jobs, "--output", os.path.join(out, "batch")], check=True,
                   stderr=subprocess.DEVNULL)
    batch_s = time.perf_counter() - start

    ray.init(num_cpus=os.cpu_count(), num_gpus=0, include_dashboard=False, log_to_driver=False)
    start = time.perf_counter()
    summary = chiaro.ray.render_dataset(jobs, os.path.join(out, "ray"), num_workers=args.workers, gpus_per_worker=0)
    ray_s = time.perf_counter() - start
    ray.shutdown()
    if summary["done"] != args.jobs:
        sys.exit("ray: %s" % summary)

    size = "%dx%d rgb+depth" % (args.width, args.height)
    print("| way (%s, %d jobs) | wall time | jobs per minute |" % (size, args.jobs))
    print("|---|---|---|")
    print("| chiaro batch, 1 process | %.1f s | %.0f |" % (batch_s, args.jobs * 60 / batch_s))
    print("| chiaro.ray.render_dataset, %d workers | %.1f s | %.0f |" % (args.workers, ray_s, args.jobs * 60 / ray_s))
    print("ray / batch: %.2fx" % (batch_s / ray_s))
    differing = 0
    for i in range(args.jobs):
        folder = "frame-%04d" % i
        for name in ("rgb.png", "depth.exr"):
            same = filecmp.cmp(os.path.join(out, "batch", folder, name), os.path.join(out, "ray", folder, name),
                               shallow=False)
            differing += not same
    print("files differing between the two ways: %d" % differing)


if __name__ == "__main__":
    main()
