#!/usr/bin/env python3
"""Chiaro's Python renderer against pyrender on one scene, in one run, alternating.

Writes a scene by code (30 boxes on a 20 m floor, one sun and four spot lights, every
light shadowed: pyrender's limits), then times, ROUNDS times in turn:
  - pyrender: the shared peer program (../shared/peers/pyrender-bench/bench.py) in its
    own virtual environment, OffscreenRenderer.render returning colour and depth;
  - chiaro Renderer.render(outputs=("rgb", "depth")), one call per frame;
  - chiaro Renderer.render_many over the same camera repeated, two frames in flight.
All at WIDTH x HEIGHT, after warm-up frames. Prints each one's median frame time and
frames per second, and the ratios to pyrender.

usage: pyrender_compare.py PYRENDER_PYTHON PEER_BENCH_PY [--width 640 --height 480
       --frames 20 --warmup 3 --rounds 2 --out DIR]
"""

import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import chiaro

# The glTF writing helpers the tests use (box geometry, embedded buffers, rotations).
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests"))
from scenes import box_geometry, embed_meshes, look_at_quat, quat_from_to  # noqa: E402


def write_scene(path, seed=3):
    rng = np.random.default_rng(seed)
    mesh_data = embed_meshes([("floor", box_geometry(np.array([-10, -0.1, -10]), np.array([10, 0, 10])), 0),
                              ("box", box_geometry(np.array([-0.5, 0, -0.5]), np.array([0.5, 1, 0.5])), 1)])
    nodes = [{"name": "floor", "mesh": 0}]
    for k in range(30):
        x, z = rng.uniform(-8, 8, 2)
        s = rng.uniform(0.4, 1.4, 3)
        nodes.append({"name": "box %d" % k, "mesh": 1, "translation": [float(x), 0.0, float(z)],
                      "rotation": quat_from_to([1, 0, 0], [np.cos(k), 0, np.sin(k)]).tolist(), "scale": s.tolist()})
    lights = [{"name": "sun", "type": "directional", "intensity": 4.0}]
    nodes.append({"name": "sun", "rotation": quat_from_to([0, 0, -1], [0.5, -1.0, 0.3]).tolist(),
                  "extensions": {"KHR_lights_punctual": {"light": 0}}})
    for k in range(4):
        a = k * np.pi / 2 + 0.4
        pos = np.array([6 * np.cos(a), 5.0, 6 * np.sin(a)])
        lights.append({"name": "spot %d" % k, "type": "spot", "intensity": 60.0, "range": 25.0,
                       "color": [1.0, 0.85, 0.7], "spot": {"innerConeAngle": 0.35, "outerConeAngle": 0.6}})
        nodes.append({"name": "spot %d" % k, "translation": pos.tolist(),
                      "rotation": quat_from_to([0, 0, -1], -pos).tolist(),
                      "extensions": {"KHR_lights_punctual": {"light": k + 1}}})
    eye = np.array([12.0, 9.0, 12.0])
    nodes.append({"name": "camera", "camera": 0, "translation": eye.tolist(), "rotation": look_at_quat(eye, np.zeros(3))})
    doc = {"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_lights_punctual"],
           "extensions": {"KHR_lights_punctual": {"lights": lights}},
           "scene": 0, "scenes": [{"nodes": list(range(len(nodes)))}], "nodes": nodes,
           "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1, "zfar": 100.0}}],
           "materials": [{"name": "floor", "pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.7, 0.7, 1],
                                                                    "metallicFactor": 0, "roughnessFactor": 0.9}},
                         {"name": "clay", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.35, 0.2, 1],
                                                                   "metallicFactor": 0, "roughnessFactor": 0.6}}],
           **mesh_data}
    with open(path, "w") as fh:
        json.dump(doc, fh)


def time_pyrender(python, bench, scene, a, out):
    cmd = [python, bench, scene, str(a.width), str(a.height), str(a.warmup), str(a.frames)]
    if out:
        cmd += ["--out", os.path.join(out, "pyrender.png")]
    text = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
    line = [l for l in text.splitlines() if l.startswith("pyrender:")][-1]
    return float(re.search(r"median ([0-9.]+) ms", line).group(1)), line


def time_render(renderer, scene, a):
    for _ in range(a.warmup):
        renderer.render(scene, camera=0, width=a.width, height=a.height, outputs=("rgb", "depth"))
    times = []
    for _ in range(a.frames):
        t = time.perf_counter()
        out = renderer.render(scene, camera=0, width=a.width, height=a.height, outputs=("rgb", "depth"))
        times.append((time.perf_counter() - t) * 1e3)
    assert out["rgb"].shape == (a.height, a.width, 3)
    return statistics.median(times)


def time_render_many(renderer, scene, a):
    renderer.render_many(scene, cameras=[0] * a.warmup, width=a.width, height=a.height, outputs=("rgb", "depth"))
    t = time.perf_counter()
    frames = renderer.render_many(scene, cameras=[0] * a.frames, width=a.width, height=a.height,
                                  outputs=("rgb", "depth"))
    elapsed = (time.perf_counter() - t) * 1e3
    assert len(frames) == a.frames and frames[-1]["depth"].shape == (a.height, a.width)
    return elapsed / a.frames


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("pyrender_python")
    ap.add_argument("peer_bench")
    ap.add_argument("--width", type=int, default=640)
    ap.add_argument("--height", type=int, default=480)
    ap.add_argument("--frames", type=int, default=20)
    ap.add_argument("--warmup", type=int, default=3)
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--out", help="folder for the scene and both pictures")
    a = ap.parse_args()
    folder = a.out or tempfile.mkdtemp(prefix="chiaro-bench-")
    os.makedirs(folder, exist_ok=True)
    scene_path = os.path.join(folder, "sun-and-spots.gltf")
    write_scene(scene_path)
    scene = chiaro.load(scene_path)
    renderer = chiaro.Renderer()
    print("scene: %s (%d triangles, %d lights); %dx%d; device: %s" % (
        scene_path, scene.triangle_count, len(scene.lights), a.width, a.height, renderer.device["name"]))
    if a.out:
        rgb = renderer.render(scene, camera=0, width=a.width, height=a.height)["rgb"]
        np.save(os.path.join(folder, "chiaro-rgb.npy"), rgb)
    rows = []
    for round_ in range(1, a.rounds + 1):
        pyr, line = time_pyrender(a.pyrender_python, a.peer_bench, scene_path, a, a.out)
        one = time_render(renderer, scene, a)
        many = time_render_many(renderer, scene, a)
        rows.append((round_, pyr, one, many))
        print(line)
        print("round %d: pyrender %.1f ms (%.2f fps) | chiaro render %.1f ms (%.2f fps, %.2fx) | "
              "chiaro render_many %.1f ms (%.2f fps, %.2fx)" % (
                  round_, pyr, 1e3 / pyr, one, 1e3 / one, pyr / one, many, 1e3 / many, pyr / many))
        sys.stdout.flush()
    # A dataset's pace: 100 different views, rgb + depth + instance, in one call.
    cameras = [chiaro.Camera.look_at((14 * np.cos(t), 8.0, 14 * np.sin(t)), (0, 0, 0), yfov_deg=45.8)
               for t in np.linspace(0, 2 * np.pi, 100, endpoint=False)]
    t = time.perf_counter()
    frames = renderer.render_many(scene, cameras=cameras, width=a.width, height=a.height,
                                  outputs=("rgb", "depth", "instance"))
    elapsed = time.perf_counter() - t
    assert len(frames) == 100
    print("100 views, rgb + depth + instance, %dx%d, render_many: %.1f s (%.2f fps)" % (
        a.width, a.height, elapsed, 100 / elapsed))


if __name__ == "__main__":
    main()
