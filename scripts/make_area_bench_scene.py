#!/usr/bin/env python3
"""Writes the benchmark scene with its shadowed point and spot lights (four spots, two
points) replaced by EXT_lights_area rects, for measuring what area lights cost:

    python3 scripts/make_area_bench_scene.py IN.gltf OUT.gltf [--width 1.0] [--height 0.5]
        [--shadows pcss|soft|hard|none]

Each rect sits where its light was, at the same far-field intensity (luminance = the
light's candela over the rect's area), shining along the spot's axis or, for a point
light, straight down, with the given shadow mode. The sun and the unshadowed point lights
are kept. Buffers stay where the input's are (relative URIs resolve from OUT's folder
only if OUT is beside IN). Standard library only.
"""

from __future__ import annotations

import argparse
import json
import math
import sys

DOWN = [-math.sqrt(0.5), 0.0, 0.0, math.sqrt(0.5)]  # -Z turned to -Y: a quarter turn about X


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("input")
    ap.add_argument("output")
    ap.add_argument("--width", type=float, default=1.0)
    ap.add_argument("--height", type=float, default=0.5)
    ap.add_argument("--shadows", choices=("pcss", "soft", "hard", "none"), default="pcss")
    args = ap.parse_args(argv)
    with open(args.input) as f:
        doc = json.load(f)
    punctual = doc["extensions"]["KHR_lights_punctual"]["lights"]
    area = args.width * args.height
    rects = []
    for node in doc["nodes"]:
        reference = node.get("extensions", {}).get("KHR_lights_punctual")
        if reference is None:
            continue
        light = punctual[reference["light"]]
        shadowed = light.get("extras", {}).get("shadows", "soft") != "none"
        if light["type"] == "directional" or not shadowed:
            continue
        if light["type"] == "point":
            node["rotation"] = DOWN
        rects.append({"name": light.get("name", f"rect {len(rects)}"), "type": "rect",
                      "color": light.get("color", [1.0, 1.0, 1.0]), "intensity": light["intensity"] / area,
                      "size": args.height, "rect": {"aspect": args.width / args.height},
                      "extras": {"shadows": args.shadows}})
        del node["extensions"]["KHR_lights_punctual"]
        node["extensions"]["EXT_lights_area"] = {"light": len(rects) - 1}
    doc["extensions"]["EXT_lights_area"] = {"lights": rects}
    doc["extensionsUsed"] = sorted(set(doc.get("extensionsUsed", [])) | {"EXT_lights_area"})
    with open(args.output, "w") as f:
        json.dump(doc, f)
    print(f"make_area_bench_scene: wrote {args.output} ({len(rects)} rects of {args.width} x {args.height} m, "
          f"{args.shadows} shadows)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
