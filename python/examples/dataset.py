#!/usr/bin/env python3
"""Renders a small dataset: random cameras around a model, each sample saved as an .npz
holding rgb, depth, instance, label and one shadow mask per light.

    python dataset.py [SCENE.gltf] --samples 16 --width 320 --height 240 --out dataset/

Without a scene, the built-in demo. Each sample is written to a temporary file and renamed
into place as soon as its chunk of frames is rendered, and a sample that exists is
skipped, so a rerun resumes; the seed fixes the cameras, so the same command gives the
same files.
"""

import argparse
import os
import tempfile

import numpy as np

import chiaro


def random_cameras(scene, count, seed):
    """Cameras on a sphere around the scene's centre, above the floor, looking at it."""
    lo, hi = (np.array(b) for b in scene.bounds)
    centre = (lo + hi) / 2
    radius = max(float(np.linalg.norm(hi - lo)) / 2, 1e-3)
    rng = np.random.default_rng(seed)
    cameras = []
    for _ in range(count):
        azimuth = rng.uniform(0, 2 * np.pi)
        elevation = rng.uniform(np.radians(15), np.radians(60))
        distance = radius * rng.uniform(1.2, 1.8)
        direction = np.array([np.cos(elevation) * np.cos(azimuth), np.sin(elevation),
                              np.cos(elevation) * np.sin(azimuth)])
        cameras.append(chiaro.Camera.look_at(centre + distance * direction, centre, yfov_deg=50.0))
    return cameras


def save_atomically(path, **arrays):
    folder = os.path.dirname(path) or "."
    fd, tmp = tempfile.mkstemp(dir=folder, suffix=".npz.tmp")
    try:
        with os.fdopen(fd, "wb") as f:
            np.savez_compressed(f, **arrays)
        os.replace(tmp, path)
    except BaseException:
        os.unlink(tmp)
        raise


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scene", nargs="?", help=".gltf or .glb (default: the demo scene)")
    ap.add_argument("--samples", type=int, default=16)
    ap.add_argument("--width", type=int, default=320)
    ap.add_argument("--height", type=int, default=240)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--device", default="auto")
    ap.add_argument("--out", default="dataset")
    a = ap.parse_args(argv)

    scene = chiaro.load(a.scene) if a.scene else chiaro.Scene.demo(lights=4)
    renderer = chiaro.Renderer(device=a.device)
    os.makedirs(a.out, exist_ok=True)
    cameras = random_cameras(scene, a.samples, a.seed)
    todo = [(i, c) for i, c in enumerate(cameras) if not os.path.exists(os.path.join(a.out, "%05d.npz" % i))]
    outputs = ("rgb", "depth", "instance", "label", "shadow")
    # render_many returns every frame it renders: chunks bound the memory held and save
    # each chunk before the next renders.
    chunk = 16
    for start in range(0, len(todo), chunk):
        part = todo[start:start + chunk]
        frames = renderer.render_many(scene, cameras=[c for _, c in part], width=a.width, height=a.height,
                                      outputs=outputs)
        for (i, camera), frame in zip(part, frames):
            save_atomically(os.path.join(a.out, "%05d.npz" % i), eye=np.array(camera.eye),
                            world_from_view=np.array(camera.world_from_view),
                            shadow_lights=np.array(frame["shadow_lights"]), node_names=np.array(scene.node_names),
                            **{k: frame[k] for k in outputs})
    print("chiaro: %d samples in %s (%d rendered, %d already there) on %s" % (
        len(cameras), a.out, len(todo), len(cameras) - len(todo), renderer.device["name"]))


if __name__ == "__main__":
    main()
