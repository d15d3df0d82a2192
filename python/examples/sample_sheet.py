#!/usr/bin/env python3
"""One dataset sample as a picture: rgb, depth, instance ids, labels (when the scene has
any), and the shadow mask of each light whose shadow the view sees (the picture in
docs/python.md).

    python sample_sheet.py [SAMPLE.npz] --out sample.png

Without a sample, renders one of the demo scene. Writes PNG with numpy and zlib alone.
"""

import argparse
import struct
import zlib

import numpy as np


def write_png(path, rgb):
    h, w, _ = rgb.shape
    raw = b"".join(b"\x00" + rgb[y].tobytes() for y in range(h))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def grey(values, lo, hi):
    v = np.clip((values - lo) / max(hi - lo, 1e-9), 0, 1)
    v = np.where(np.isfinite(values), v, 1.0)
    return np.repeat((v * 255).astype(np.uint8)[..., None], 3, axis=-1)


def id_colours(ids):
    """A fixed colour per id, black for the sky."""
    rng = np.random.default_rng(7)
    palette = rng.integers(40, 256, size=(4096, 3), dtype=np.uint8)
    out = palette[ids % 4096]
    out[ids == 0xFFFFFFFF] = 0
    return out


def sheet(sample, columns=4):
    depth = sample["depth"]
    finite = depth[np.isfinite(depth)]
    lo, hi = (finite.min(), finite.max()) if finite.size else (0.0, 1.0)
    tiles = [sample["rgb"], grey(depth, lo, hi), id_colours(sample["instance"])]
    if "label" in sample and sample["label"].any():  # a scene without labels shows none
        tiles.append(id_colours(sample["label"]))
    for mask in sample["shadow"]:
        if np.nanmin(mask) < 0.99:  # the lights whose shadows this view sees
            tiles.append(grey(np.nan_to_num(mask, nan=1.0), 0, 1))
    h, w, _ = tiles[0].shape
    rows = -(-len(tiles) // columns)
    out = np.full((rows * (h + 4) - 4, columns * (w + 4) - 4, 3), 255, np.uint8)
    for k, tile in enumerate(tiles):
        r, c = divmod(k, columns)
        out[r * (h + 4):r * (h + 4) + h, c * (w + 4):c * (w + 4) + w] = tile
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("sample", nargs="?")
    ap.add_argument("--out", default="sample.png")
    a = ap.parse_args()
    if a.sample:
        sample = dict(np.load(a.sample))
    else:
        import chiaro

        scene = chiaro.Scene.demo(lights=4)
        camera = chiaro.Camera.look_at((7.0, 6.0, 9.0), (0.0, 0.5, 0.0), yfov_deg=45.0)
        sample = chiaro.Renderer().render(scene, camera=camera, width=320, height=240,
                                          outputs=("rgb", "depth", "instance", "label", "shadow"))
    write_png(a.out, sheet(sample))
    print("wrote", a.out)


if __name__ == "__main__":
    main()
