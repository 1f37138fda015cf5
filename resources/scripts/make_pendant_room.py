#!/usr/bin/env python3
"""Relume's pendant room: lamps that hang, rendered by Blender Cycles.

    python3 resources/scripts/make_pendant_room.py --out resources/pendant_room \
        [--samples 256] [--width 640] [--height 480] [--only-data] [--blender blender]

A room of the sample room's kind (resources/scripts/make_sample_room.py: the same conventions,
metres, +Z up, OpenCV cameras, a bundle in the benchmark rooms' layout) lit by three two-sided
pendants, square emissive panels hanging 0.30, 0.45 and 0.60 m below the ceiling: each lights the
ceiling above it as much as the floor below, so the ceiling's bright pool is as close to a lamp as
anything in the room. Pendant B shines at half the others' strength. The main photo shows pendant
A, other photos show B, no photo shows C (the estimate must find it from its light alone).

Surfaces are Lambertian with flat albedos (scene.json's `albedo` is the whole truth), rendered by
resources/scripts/render_bundle.py (unbiased: 12 diffuse bounces, no clamping). Besides the photos
and the variants' truth images it renders the main photo a second time with another sampling seed
(photos/main_seed7.exr), and the variant A_off too (truth/A_off_seed7.exr): `relume compare
BUNDLE/photos/main_seed7.exr BUNDLE --truth photo` (and `truth/A_off_seed7.exr ... --truth A_off`)
give the renders' own noise floor. EXR files are written as half floats (zip), PNGs as the bundles'
png_encoding says.
"""
import argparse
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import make_sample_room as base  # noqa: E402  (its helpers; nothing of Blender is imported)
import rerender_bundle  # noqa: E402

ROOM = [4.4, 5.6, 2.8]
PANEL = 0.30
MATERIALS = {
    "floor": [0.36, 0.27, 0.18],
    "ceiling": [0.80, 0.80, 0.78],
    "wall": [0.70, 0.68, 0.62],
    "wall_accent": [0.45, 0.62, 0.55],
    "table": [0.50, 0.36, 0.22],
    "box": [0.25, 0.38, 0.62],
    "cabinet": [0.62, 0.58, 0.50],
}
PENDANTS = [
    # name, centre (x, y), drop below the ceiling (m), radiance (linear RGB, each face)
    ("A", (2.10, 4.35), 0.30, [22.0, 21.0, 18.0]),
    ("B", (3.30, 2.2), 0.60, [11.0, 11.0, 11.0]),
    ("C", (1.35, 1.9), 0.45, [18.0, 19.5, 22.0]),
]
VIEWS = [
    # name, eye, target
    ("main", [2.2, 0.3, 1.45], [1.6, 3.4, 1.05]),
    ("view0", [0.5, 0.4, 1.5], [2.4, 3.6, 0.7]),
    ("view1", [3.9, 0.5, 1.5], [2.0, 3.6, 0.7]),
    ("view2", [1.4, 0.35, 2.2], [2.3, 3.3, 0.3]),
    ("view3", [0.6, 3.2, 1.3], [3.6, 2.1, 1.5]),
    ("view4", [0.5, 1.4, 1.7], [3.4, 3.9, 0.5]),
    ("view5", [3.9, 1.2, 1.8], [1.2, 4.2, 0.5]),
]
NO_SHADOW = "table,box"  # truth/unoccluded: these cast no shadows


def polygon(name, group, kind, material, verts):
    return {"name": name, "group": group, "kind": kind, "material": material,
            "vertices": [[round(c, 6) for c in v] for v in verts],
            "albedo": MATERIALS[material] if kind == "real" else None}


def build_room():
    W, D, H = ROOM
    q = base.quad
    polys = [
        polygon("floor", "floor", "real", "floor", q([0, 0, 0], [W, 0, 0], [0, D, 0])),
        polygon("ceiling", "ceiling", "real", "ceiling", q([0, 0, H], [0, D, 0], [W, 0, 0])),
        polygon("wall_back", "wall_back", "real", "wall", q([0, D, 0], [W, 0, 0], [0, 0, H])),
        polygon("wall_front", "wall_front", "real", "wall", q([W, 0, 0], [-W, 0, 0], [0, 0, H])),
        polygon("wall_left", "wall_left", "real", "wall_accent", q([0, 0, 0], [0, D, 0], [0, 0, H])),
        polygon("wall_right", "wall_right", "real", "wall", q([W, D, 0], [0, -D, 0], [0, 0, H])),
    ]

    def box(prefix, group, material, lo, hi, bottom=False):
        for suffix, verts in base.box_faces(lo, hi, bottom):
            polys.append(polygon(prefix + suffix, group, "real", material, verts))

    # A table under pendant A and C's light, its top a slab with an underside, four legs.
    tx0, ty0, tx1, ty1, th, tt = 0.95, 2.55, 2.25, 3.45, 0.74, 0.04
    box("table_top", "table", "table", [tx0, ty0, th - tt], [tx1, ty1, th], bottom=True)
    leg = 0.06
    for i, (lx, ly) in enumerate([(tx0 + 0.05, ty0 + 0.05), (tx1 - 0.05 - leg, ty0 + 0.05),
                                  (tx1 - 0.05 - leg, ty1 - 0.05 - leg), (tx0 + 0.05, ty1 - 0.05 - leg)]):
        for suffix, verts in base.box_faces([lx, ly, 0], [lx + leg, ly + leg, th - tt]):
            if suffix != "_top":  # (under the table top)
                polys.append(polygon(f"table_leg{i}{suffix}", "table", "real", "table", verts))
    # A box on the floor under pendant B, a cabinet against the back wall.
    box("box", "box", "box", [2.9, 3.4, 0.0], [3.6, 4.0, 0.55])
    box("cabinet", "cabinet", "cabinet", [0.3, D - 0.45, 0.0], [1.5, D - 0.0, 0.9])
    # Pendants: square panels facing down, emitting from both faces.
    for name, (cx, cy), drop, _ in PENDANTS:
        s = PANEL / 2
        z = H - drop
        polys.append(polygon("light_" + name, "light_" + name, "light", "ceiling",
                             q([cx - s, cy - s, z], [0, 2 * s, 0], [2 * s, 0, 0])))
    # The cabinet's back face lies on the wall: nothing sees it.
    return [p for p in polys if p["name"] != "cabinet_back"]


def write_data(out, width, height, samples):
    polys = build_room()
    fx = 0.6667 * width
    K = [[fx, 0, width / 2.0], [0, fx, height / 2.0], [0, 0, 1]]
    photos = []
    for name, eye, target in VIEWS:
        R, t = base.look_at(eye, target)
        photos.append({"name": name, "file": f"photos/{name}.png", "hdr": f"photos/{name}.exr",
                       "K": K, "R": R, "t": t, "width": width, "height": height})
    lights = []
    for name, _, drop, rad in PENDANTS:
        poly = next(p for p in polys if p["name"] == "light_" + name)
        strength = max(rad)
        lights.append({"name": name, "polygon": poly["vertices"], "color": [c / strength for c in rad],
                       "strength": strength, "radiance_rgb": rad, "two_sided": True,
                       "hangs_below_ceiling_m": drop})
    variants = [{"name": f"{n}_off", "lights": {n: 0}, "file": f"truth/{n}_off.png", "hdr": f"truth/{n}_off.exr"}
                for n, _, _, _ in PENDANTS]
    variants.append({"name": "C_double", "lights": {"C": 2}, "file": "truth/C_double.png", "hdr": "truth/C_double.exr"})
    scene = {
        "generator": f"Relume resources/scripts/make_pendant_room.py, Blender Cycles, {samples} spp, "
                     "diffuse-only, flat albedos, two-sided pendants",
        "units": "metres", "up": "+Z", "room": ROOM, "polygons": polys, "lights": lights,
        "photos": photos, "main_photo": "main", "variants": variants,
        "unoccluded": "truth/unoccluded.png", "unoccluded_no_shadow": NO_SHADOW.split(","),
        "camera_convention": "OpenCV: x_cam = R * X_world + t, x right, y down, z forward; K in pixels",
        "png_encoding": "sRGB 8-bit, Standard view transform, exposure 0",
        "exr_encoding": "linear scene radiance, half float",
    }
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "scene.json"), "w") as f:
        json.dump(scene, f, indent=1)
    base.write_geometry_obj(os.path.join(out, "geometry.obj"), polys,
                            "# Relume pendant room, metres, Z up; one group per polygon\n")
    base.write_colmap(out, photos, width, height, fx)
    return scene


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default="resources/pendant_room")
    ap.add_argument("--samples", type=int, default=256)
    ap.add_argument("--width", type=int, default=640)
    ap.add_argument("--height", type=int, default=480)
    ap.add_argument("--only-data", action="store_true")
    ap.add_argument("--blender", default="blender")
    a = ap.parse_args()
    desc = write_data(a.out, a.width, a.height, a.samples)
    if a.only_data:
        return
    os.makedirs(os.path.join(a.out, "photos"), exist_ok=True)
    os.makedirs(os.path.join(a.out, "truth"), exist_ok=True)
    samples = ["--samples", str(a.samples)]
    jobs = [(ph["hdr"], ph["file"], ["--camera", ph["name"]]) for ph in desc["photos"]]
    jobs += [(v["hdr"], v["file"], ["--variant", v["name"]]) for v in desc["variants"]]
    jobs.append(("truth/unoccluded.exr", "truth/unoccluded.png", ["--no-shadow", NO_SHADOW]))
    jobs.append(("photos/main_seed7.exr", None, ["--seed", "7"]))
    jobs.append(("truth/A_off_seed7.exr", None, ["--variant", "A_off", "--seed", "7"]))
    for i, (hdr, png, extra) in enumerate(jobs):
        print("make_pendant_room.py: [%d/%d] %s" % (i + 1, len(jobs), hdr), file=sys.stderr, flush=True)
        exr = os.path.join(a.out, hdr)
        rerender_bundle.render(a.blender, a.out, exr, samples + extra)
        rerender_bundle.to_half(exr)
        if png:
            rerender_bundle.to_png(exr, os.path.join(a.out, png))


if __name__ == "__main__":
    main()
