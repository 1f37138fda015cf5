"""Relume's own daylight sample room: a room lit only through its window by a measured sky.

Run inside Blender (Debian's `blender` package, Cycles on the CPU):

    blender -b --factory-startup -P resources/scripts/make_daylight_room.py -- \
        --out resources/daylight_room [--samples 384] [--width 320] [--height 240] [--fisheye 256] \
        [--only-data | --skies-only]

It writes a daylight bundle in the layout `relume` reads (scene.json with a "daylight" section,
geometry.obj, colmap/, photos/*.png|exr, sky/fisheye_*.exr|png, truth/*.png|exr): the photos under
the sky `sun0`, and as truth the main view under two other suns and with a virtual box under two
suns. The sky is Blender's Nishita model (a clear sky with its sun disc); each sky is captured by
an equidistant 180-degree fisheye looking straight up from just above the roof, image up = +Y,
the circle filling the square image — what a photographer would take on the roof with an HDR
bracket, saved as full-float EXR (half float's largest value, 65504, would clip the sun's
pixels and understate and discolour its light). Lamps: none (the room is lit by daylight only).

Geometry is in metres, +Z up; the window is an opening (kind "window": no geometry in the
render); the outside ground is a large grey polygon just below the floor's level (group
"outside"). Cameras follow OpenCV: x_cam = R * X_world + t, x right, y down, z forward.
"""

import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from make_sample_room import (add_camera, add_mesh_object, box_faces, diffuse_material, look_at, quad,  # noqa: E402
                              script_options, setup_cycles, shoot, write_colmap, write_geometry_obj)

ROOM = [3.8, 4.4, 2.6]  # x (width), y (depth), z (height)
# The window: in the right wall (x = ROOM[0]), y from WIN_Y0 to WIN_Y1, z from WIN_Z0 to WIN_Z1.
WIN_Y0, WIN_Y1, WIN_Z0, WIN_Z1 = 1.5, 2.8, 0.85, 2.05
SKY_STRENGTH = 0.25

MATERIALS = {
    "floor": {"albedo": [0.40, 0.31, 0.22], "pattern": "planks"},
    "ceiling": {"albedo": [0.80, 0.80, 0.78], "pattern": "noise"},
    "wall": {"albedo": [0.72, 0.70, 0.64], "pattern": "noise"},
    "wall_accent": {"albedo": [0.52, 0.60, 0.70], "pattern": "noise"},
    "table": {"albedo": [0.48, 0.34, 0.22], "pattern": "noise"},
    "crate": {"albedo": [0.30, 0.50, 0.34], "pattern": "noise"},
    "ground": {"albedo": [0.22, 0.21, 0.19], "pattern": "noise"},
    "virtual_box": {"albedo": [0.80, 0.38, 0.06], "pattern": "flat"},
}

# name, sun elevation and rotation (Blender's Nishita sky: rotation about +Z, 0 = the sun towards
# +Y, 90 = towards +X, the window's side).
SKIES = [("sun0", 30.0, 100.0), ("sun1", 48.0, 70.0), ("sun2", 22.0, 112.0)]

VIRTUAL_BOX = {"name": "orange_box", "box_min": [2.1, 1.95, 0.0], "box_max": [2.45, 2.3, 0.35],
               "albedo": MATERIALS["virtual_box"]["albedo"]}

VIEWS = [
    # name, eye, target
    ("main", [0.9, 0.15, 1.75], [2.1, 2.6, 0.3]),
    ("view0", [0.4, 0.4, 1.5], [2.9, 3.0, 0.6]),
    ("view1", [3.3, 0.35, 1.7], [1.0, 3.3, 0.6]),
    ("view2", [0.5, 3.9, 1.6], [3.2, 1.6, 0.7]),
]

polygons = []


def add_polygon(name, group, kind, material, verts):
    albedo = MATERIALS[material]["albedo"] if kind == "real" else None
    polygons.append({"name": name, "group": group, "kind": kind, "material": material,
                     "vertices": [[round(c, 6) for c in v] for v in verts], "albedo": albedo})


def add_box(prefix, group, material, lo, hi):
    """Axis-aligned box standing on something (no bottom face), outward normals."""
    for suffix, verts in box_faces(lo, hi):
        add_polygon(prefix + suffix, group, "real", material, verts)


def build_room():
    W, D, H = ROOM
    add_polygon("floor", "floor", "real", "floor", quad([0, 0, 0], [W, 0, 0], [0, D, 0]))
    add_polygon("ceiling", "ceiling", "real", "ceiling", quad([0, 0, H], [0, D, 0], [W, 0, 0]))
    add_polygon("wall_back", "wall_back", "real", "wall", quad([0, D, 0], [W, 0, 0], [0, 0, H]))
    add_polygon("wall_front", "wall_front", "real", "wall", quad([W, 0, 0], [-W, 0, 0], [0, 0, H]))
    add_polygon("wall_left", "wall_left", "real", "wall_accent", quad([0, 0, 0], [0, D, 0], [0, 0, H]))
    # The right wall around its window (normals inward, -X), and the window itself.
    add_polygon("wall_right_below", "wall_right", "real", "wall", quad([W, D, 0], [0, -D, 0], [0, 0, WIN_Z0]))
    add_polygon("wall_right_above", "wall_right", "real", "wall", quad([W, D, WIN_Z1], [0, -D, 0], [0, 0, H - WIN_Z1]))
    add_polygon("wall_right_front", "wall_right", "real", "wall",
                quad([W, WIN_Y0, WIN_Z0], [0, -WIN_Y0, 0], [0, 0, WIN_Z1 - WIN_Z0]))
    add_polygon("wall_right_back", "wall_right", "real", "wall",
                quad([W, D, WIN_Z0], [0, WIN_Y1 - D, 0], [0, 0, WIN_Z1 - WIN_Z0]))
    add_polygon("window", "window", "window", None,
                quad([W, WIN_Y1, WIN_Z0], [0, WIN_Y0 - WIN_Y1, 0], [0, 0, WIN_Z1 - WIN_Z0]))
    # Outside: the ground beyond the window wall, 1 mm below the floor's level.
    add_polygon("ground", "outside", "real", "ground", quad([W, -20.0, -0.001], [36.0, 0, 0], [0, 60.0, 0]))
    # A table (top slab and four legs) and a crate on the floor.
    tx0, ty0, tx1, ty1, th, tt = 0.8, 2.7, 1.9, 3.5, 0.74, 0.04
    add_box("table_top", "table", "table", [tx0, ty0, th - tt], [tx1, ty1, th])
    add_polygon("table_top_bottom", "table", "real", "table",
                quad([tx0, ty0, th - tt], [0, ty1 - ty0, 0], [tx1 - tx0, 0, 0]))
    leg = 0.06
    for i, (lx, ly) in enumerate([(tx0 + 0.05, ty0 + 0.05), (tx1 - 0.05 - leg, ty0 + 0.05),
                                  (tx1 - 0.05 - leg, ty1 - 0.05 - leg), (tx0 + 0.05, ty1 - 0.05 - leg)]):
        add_box(f"table_leg{i}", "table", "table", [lx, ly, 0], [lx + leg, ly + leg, th - tt])
    add_box("crate", "crate", "crate", [2.55, 3.55, 0.0], [3.15, 4.05, 0.45])


def sun_direction(elevation_deg, rotation_deg):
    """The direction towards the sun in the room's frame, as Blender's Nishita sky places it."""
    e, r = math.radians(elevation_deg), math.radians(rotation_deg)
    return [math.cos(e) * math.sin(r), math.cos(e) * math.cos(r), math.sin(e)]


def write_data(out, width, height, samples):
    fx = 0.6667 * width
    K = [[fx, 0, width / 2.0], [0, fx, height / 2.0], [0, 0, 1]]
    photos = []
    for name, eye, target in VIEWS:
        R, t = look_at(eye, target)
        photos.append({"name": name, "file": f"photos/{name}.png", "hdr": f"photos/{name}.exr",
                       "K": K, "R": R, "t": t, "width": width, "height": height})
    W, D, H = ROOM
    fisheye_at = [W / 2, D / 2, H + 0.05]
    skies = [{"name": name, "sun_elevation_deg": e, "sun_rotation_deg": r,
              "sun_direction": [round(c, 6) for c in sun_direction(e, r)],
              "fisheye": f"sky/fisheye_{name}.exr",
              "fisheye_model": "equidistant, 180 deg, looking up (+Z), image up = +Y",
              "fisheye_position": fisheye_at} for name, e, r in SKIES]
    variants = [
        {"name": "sun1", "sun": "sun1", "file": "truth/sun1.png", "hdr": "truth/sun1.exr"},
        {"name": "sun2", "sun": "sun2", "file": "truth/sun2.png", "hdr": "truth/sun2.exr"},
        {"name": "virtual_box_sun0", "sun": "sun0", "virtual_objects": [VIRTUAL_BOX],
         "file": "truth/virtual_box_sun0.png", "hdr": "truth/virtual_box_sun0.exr"},
        {"name": "virtual_box_sun1", "sun": "sun1", "virtual_objects": [VIRTUAL_BOX],
         "file": "truth/virtual_box_sun1.png", "hdr": "truth/virtual_box_sun1.exr"},
    ]
    scene = {
        "generator": f"Relume resources/scripts/make_daylight_room.py, Blender Cycles, {samples} spp, diffuse-only",
        "units": "metres", "up": "+Z", "room": ROOM, "polygons": polygons, "lights": [],
        "photos": photos, "main_photo": "main", "variants": variants,
        "unoccluded": "truth/unoccluded.png",
        "camera_convention": "OpenCV: x_cam = R * X_world + t, x right, y down, z forward; K in pixels",
        "png_encoding": "sRGB 8-bit, Standard view transform, exposure 0",
        "exr_encoding": "linear scene radiance",
        "daylight": {"sky_model": f"Nishita (Blender), strength {SKY_STRENGTH}", "photos_sun": "sun0",
                     "lamps": "none", "sky": skies},
    }
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "scene.json"), "w") as f:
        json.dump(scene, f, indent=1)
    write_geometry_obj(os.path.join(out, "geometry.obj"), polygons,
                       "# Relume daylight sample room, metres, Z up; one group per polygon\n")
    write_colmap(out, photos, width, height, fx)
    return scene


def render(out, scene_desc, samples, fisheye_size, skies_only=False):
    import bpy

    sc = setup_cycles(bpy, samples, scene_desc["photos"][0]["width"], scene_desc["photos"][0]["height"])
    nt = sc.world.node_tree
    sky = nt.nodes.new("ShaderNodeTexSky")
    sky.sky_type = "NISHITA"
    sky.sun_disc = True
    bg = nt.nodes["Background"]
    bg.inputs[1].default_value = SKY_STRENGTH
    nt.links.new(sky.outputs["Color"], bg.inputs["Color"])

    mats = {k: diffuse_material(bpy, k, v) for k, v in MATERIALS.items()}
    groups, objects = {}, {}
    for p in scene_desc["polygons"]:
        if p["kind"] == "real":  # the window is an opening
            groups.setdefault(p["group"], []).append(p)
    for group, polys in groups.items():
        objects[group] = add_mesh_object(bpy, sc, group, polys, mats[polys[0]["material"]])
    # The virtual box, shown only in its variants.
    lo, hi = VIRTUAL_BOX["box_min"], VIRTUAL_BOX["box_max"]
    box_polys = [{"vertices": verts} for _, verts in box_faces(lo, hi)]
    box = add_mesh_object(bpy, sc, "virtual_box", box_polys, mats["virtual_box"])

    cams = {ph["name"]: add_camera(bpy, sc, ph) for ph in scene_desc["photos"]}
    # The sky camera: equidistant fisheye, 180 degrees, looking up (+Z), image up = +Y.
    import mathutils

    fd = bpy.data.cameras.new("fisheye")
    fd.type = "PANO"
    for holder in (fd, getattr(fd, "cycles", None)):
        if holder is not None and hasattr(holder, "panorama_type"):
            holder.panorama_type = "FISHEYE_EQUIDISTANT"
            holder.fisheye_fov = math.pi
    fo = bpy.data.objects.new("fisheye", fd)
    pos = scene_desc["daylight"]["sky"][0]["fisheye_position"]
    # Blender's camera looks along its -Z with +Y up: world +Z forward, +Y up, so x = -X.
    fo.matrix_world = mathutils.Matrix(((-1, 0, 0, pos[0]), (0, 1, 0, pos[1]), (0, 0, -1, pos[2]), (0, 0, 0, 1)))
    sc.collection.objects.link(fo)

    skies = {s["name"]: s for s in scene_desc["daylight"]["sky"]}

    def set_sky(name):
        s = skies[name]
        sky.sun_elevation = math.radians(s["sun_elevation_deg"])
        sky.sun_rotation = math.radians(s["sun_rotation_deg"])

    for d in ("photos", "truth", "sky"):
        os.makedirs(os.path.join(out, d), exist_ok=True)
    size = (sc.render.resolution_x, sc.render.resolution_y)
    for s in scene_desc["daylight"]["sky"]:
        set_sky(s["name"])
        sc.render.resolution_x = sc.render.resolution_y = fisheye_size
        box.hide_render = True
        # Full float: the sun's pixels are far brighter than half float's largest value (65504),
        # which would clip the sun and shift its colour.
        shoot(bpy, sc, fo, out, s["fisheye"].replace(".exr", ".png"), s["fisheye"], "daylight room", depth="32")
    if skies_only:
        return
    sc.render.resolution_x, sc.render.resolution_y = size
    set_sky(scene_desc["daylight"]["photos_sun"])
    for ph in scene_desc["photos"]:
        shoot(bpy, sc, cams[ph["name"]], out, ph["file"], ph["hdr"], "daylight room")
    for v in scene_desc["variants"]:
        set_sky(v["sun"])
        box.hide_render = not v.get("virtual_objects")
        shoot(bpy, sc, cams[scene_desc["main_photo"]], out, v["file"], v["hdr"], "daylight room")
    # Unoccluded: the photos' sky, the table and the crate cast no shadows.
    set_sky(scene_desc["daylight"]["photos_sun"])
    box.hide_render = True
    for g in ("table", "crate"):
        objects[g].visible_shadow = False
    shoot(bpy, sc, cams[scene_desc["main_photo"]], out, "truth/unoccluded.png", "truth/unoccluded.exr", "daylight room")


def main():
    o = script_options({"out": "resources/daylight_room", "samples": 384, "width": 320, "height": 240, "fisheye": 256,
                        "only_data": False, "skies_only": False})
    build_room()
    desc = write_data(o["out"], o["width"], o["height"], o["samples"])
    if not o["only_data"]:
        render(o["out"], desc, o["samples"], o["fisheye"], o["skies_only"])


if __name__ == "__main__":
    main()
