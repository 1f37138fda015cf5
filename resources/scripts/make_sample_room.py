"""Relume's own sample room: geometry, cameras and Blender Cycles renders.

Run inside Blender (Debian's `blender` package, Cycles on the CPU):

    blender -b --factory-startup -P resources/scripts/make_sample_room.py -- \
        --out resources/sample_room [--samples 256] [--width 640] [--height 480] [--only-data]

It writes a bundle in the layout of the benchmark rooms (scene.json, geometry.obj,
colmap/cameras.txt + images.txt, photos/*.png|exr, truth/*.png|exr). All geometry is defined
here in metres, +Z up; polygons are convex, counter-clockwise seen from the side their normal
points to; the room shell's normals point inward. Surfaces are diffuse only, with a procedural
texture whose mean is the polygon's `albedo`. Lamps are one-sided emissive quads (their back
face is black) 2 cm below the ceiling, facing down.

Cameras follow OpenCV: x_cam = R * X_world + t, x right, y down, z forward.
"""

import json
import math
import os
import sys

# ---------------------------------------------------------------------------------------------
# Small vector helpers (no numpy: Blender's bundled Python may lack it, plain python3 too)


def sub(a, b):
    return [a[i] - b[i] for i in range(3)]


def add(a, b):
    return [a[i] + b[i] for i in range(3)]


def scale(a, s):
    return [a[i] * s for i in range(3)]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def dot(a, b):
    return sum(a[i] * b[i] for i in range(3))


def normalize(a):
    n = math.sqrt(dot(a, a))
    return [x / n for x in a]


# ---------------------------------------------------------------------------------------------
# The room

ROOM = [4.0, 5.2, 2.6]  # x (width), y (depth), z (height)
LAMP_DROP = 0.02
LAMP_SIZE = 0.30

MATERIALS = {
    "floor": {"albedo": [0.36, 0.27, 0.18], "pattern": "planks"},
    "ceiling": {"albedo": [0.80, 0.80, 0.78], "pattern": "noise"},
    "wall": {"albedo": [0.70, 0.68, 0.62], "pattern": "noise"},
    "wall_accent": {"albedo": [0.45, 0.62, 0.55], "pattern": "noise"},
    "poster": {"albedo": [0.78, 0.30, 0.22], "pattern": "stripes"},
    "table": {"albedo": [0.50, 0.36, 0.22], "pattern": "noise"},
    "box": {"albedo": [0.25, 0.38, 0.62], "pattern": "noise"},
}

LAMPS = [
    # name, centre (x, y), radiance (linear RGB, the EXR pixel units)
    ("A", (1.15, 1.75), [34.0, 32.0, 27.0]),
    ("B", (2.90, 1.95), [30.0, 30.0, 30.0]),
    ("C", (2.00, 3.90), [27.0, 29.0, 34.0]),
]

polygons = []


def add_polygon(name, group, kind, material, verts):
    albedo = MATERIALS[material]["albedo"] if kind == "real" else None
    polygons.append({"name": name, "group": group, "kind": kind, "material": material,
                     "vertices": [[round(c, 6) for c in v] for v in verts], "albedo": albedo})


def quad(origin, u, v):
    """Counter-clockwise quad seen from the side of u x v."""
    return [origin, add(origin, u), add(add(origin, u), v), add(origin, v)]


def box_faces(lo, hi, bottom=False):
    """An axis-aligned box's faces with outward normals, as (suffix, vertices); `bottom` adds the
    downward face (a box standing on something has none)."""
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    dx, dy, dz = x1 - x0, y1 - y0, z1 - z0
    faces = [("_top", quad([x0, y0, z1], [dx, 0, 0], [0, dy, 0]))]
    if bottom:
        faces.append(("_bottom", quad([x0, y0, z0], [0, dy, 0], [dx, 0, 0])))
    faces += [("_front", quad([x0, y0, z0], [dx, 0, 0], [0, 0, dz])),
              ("_back", quad([x1, y1, z0], [-dx, 0, 0], [0, 0, dz])),
              ("_left", quad([x0, y1, z0], [0, -dy, 0], [0, 0, dz])),
              ("_right", quad([x1, y0, z0], [0, dy, 0], [0, 0, dz]))]
    return faces


def add_box(prefix, group, material, lo, hi, bottom=False):
    for suffix, verts in box_faces(lo, hi, bottom):
        add_polygon(prefix + suffix, group, "real", material, verts)


def build_room():
    W, D, H = ROOM
    # Shell, normals inward.
    add_polygon("floor", "floor", "real", "floor", quad([0, 0, 0], [W, 0, 0], [0, D, 0]))
    add_polygon("ceiling", "ceiling", "real", "ceiling", quad([0, 0, H], [0, D, 0], [W, 0, 0]))
    add_polygon("wall_back", "wall_back", "real", "wall", quad([0, D, 0], [W, 0, 0], [0, 0, H]))
    add_polygon("wall_front", "wall_front", "real", "wall", quad([W, 0, 0], [-W, 0, 0], [0, 0, H]))
    add_polygon("wall_left", "wall_left", "real", "wall_accent", quad([0, 0, 0], [0, D, 0], [0, 0, H]))
    add_polygon("wall_right", "wall_right", "real", "wall", quad([W, D, 0], [0, -D, 0], [0, 0, H]))
    # Poster on the back wall, 5 mm in front of it.
    add_polygon("poster", "poster", "real", "poster", quad([2.3, D - 0.005, 1.0], [0.7, 0, 0], [0, 0, 0.95]))
    # Table: top slab (with its underside) and four legs.
    tx0, ty0, tx1, ty1, th, tt = 1.2, 2.3, 2.4, 3.1, 0.74, 0.04
    add_box("table_top", "table", "table", [tx0, ty0, th - tt], [tx1, ty1, th], bottom=True)
    leg = 0.06
    for i, (lx, ly) in enumerate([(tx0 + 0.05, ty0 + 0.05), (tx1 - 0.05 - leg, ty0 + 0.05),
                                  (tx1 - 0.05 - leg, ty1 - 0.05 - leg), (tx0 + 0.05, ty1 - 0.05 - leg)]):
        x0, y0 = lx, ly
        x1, y1 = lx + leg, ly + leg
        z1 = th - tt
        add_polygon(f"table_leg{i}_front", "table", "real", "table", quad([x0, y0, 0], [leg, 0, 0], [0, 0, z1]))
        add_polygon(f"table_leg{i}_back", "table", "real", "table", quad([x1, y1, 0], [-leg, 0, 0], [0, 0, z1]))
        add_polygon(f"table_leg{i}_left", "table", "real", "table", quad([x0, y1, 0], [0, -leg, 0], [0, 0, z1]))
        add_polygon(f"table_leg{i}_right", "table", "real", "table", quad([x1, y0, 0], [0, leg, 0], [0, 0, z1]))
    # A box on the floor near the right wall (no bottom face: it stands on the floor).
    add_box("box", "box", "box", [2.75, 3.2, 0.0], [3.3, 3.65, 0.5])
    # Lamps: emissive quads facing down.
    for name, (cx, cy), _ in LAMPS:
        s = LAMP_SIZE / 2
        z = H - LAMP_DROP
        add_polygon("light_" + name, "light_" + name, "light", "light_" + name,
                    quad([cx - s, cy - s, z], [0, 2 * s, 0], [2 * s, 0, 0]))


# ---------------------------------------------------------------------------------------------
# Cameras


def look_at(eye, target, up=(0, 0, 1)):
    """OpenCV rotation (rows: camera x right, y down, z forward in world) and translation."""
    z = normalize(sub(target, eye))
    x = normalize(cross(z, list(up)))
    y = cross(z, x)
    R = [x, y, z]
    t = [-dot(R[i], eye) for i in range(3)]
    return R, t


VIEWS = [
    # name, eye, target
    ("main", [2.0, 0.25, 1.65], [1.85, 3.3, 0.55]),
    ("view0", [0.45, 0.35, 1.55], [2.1, 3.2, 0.6]),
    ("view1", [3.55, 0.35, 1.55], [1.9, 3.2, 0.6]),
    ("view2", [1.2, 0.3, 2.1], [2.0, 2.9, 0.4]),
    ("view3", [3.0, 0.6, 1.2], [1.6, 3.0, 0.7]),
    ("view4", [0.5, 1.6, 1.7], [3.0, 3.4, 0.5]),
    ("view5", [3.5, 1.4, 1.8], [1.0, 3.6, 0.6]),
]


def rot_to_quat(R):
    """COLMAP quaternion (w, x, y, z) of a rotation matrix (rows)."""
    tr = R[0][0] + R[1][1] + R[2][2]
    if tr > 0:
        s = math.sqrt(tr + 1.0) * 2
        return [0.25 * s, (R[2][1] - R[1][2]) / s, (R[0][2] - R[2][0]) / s, (R[1][0] - R[0][1]) / s]
    if R[0][0] > R[1][1] and R[0][0] > R[2][2]:
        s = math.sqrt(1.0 + R[0][0] - R[1][1] - R[2][2]) * 2
        return [(R[2][1] - R[1][2]) / s, 0.25 * s, (R[0][1] + R[1][0]) / s, (R[0][2] + R[2][0]) / s]
    if R[1][1] > R[2][2]:
        s = math.sqrt(1.0 + R[1][1] - R[0][0] - R[2][2]) * 2
        return [(R[0][2] - R[2][0]) / s, (R[0][1] + R[1][0]) / s, 0.25 * s, (R[1][2] + R[2][1]) / s]
    s = math.sqrt(1.0 + R[2][2] - R[0][0] - R[1][1]) * 2
    return [(R[1][0] - R[0][1]) / s, (R[0][2] + R[2][0]) / s, (R[1][2] + R[2][1]) / s, 0.25 * s]


# ---------------------------------------------------------------------------------------------
# Writing the bundle's data files


def write_geometry_obj(path, polys, header):
    """The polygons as an OBJ: one object per polygon, its group and its material."""
    with open(path, "w") as f:
        f.write(header)
        n = 1
        for p in polys:
            f.write(f"o {p['name']}\ng {p['group']}\nusemtl {p['material']}\n")
            for v in p["vertices"]:
                f.write("v %.6f %.6f %.6f\n" % tuple(v))
            f.write("f " + " ".join(str(n + i) for i in range(len(p["vertices"]))) + "\n")
            n += len(p["vertices"])


def write_colmap(out, photos, width, height, fx):
    """COLMAP text model of the photos (one PINHOLE camera), as a reconstruction would give it."""
    os.makedirs(os.path.join(out, "colmap"), exist_ok=True)
    with open(os.path.join(out, "colmap", "cameras.txt"), "w") as f:
        f.write("# Camera list with one line of data per camera:\n#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n")
        f.write(f"1 PINHOLE {width} {height} {fx} {fx} {width / 2.0} {height / 2.0}\n")
    with open(os.path.join(out, "colmap", "images.txt"), "w") as f:
        f.write("# IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n# POINTS2D[] as (X, Y, POINT3D_ID)\n")
        for i, p in enumerate(photos):
            q = rot_to_quat(p["R"])
            f.write(f"{i + 1} {q[0]} {q[1]} {q[2]} {q[3]} {p['t'][0]} {p['t'][1]} {p['t'][2]} 1 {p['name']}.png\n\n")


def write_data(out, width, height, samples):
    fx = 0.6667 * width
    K = [[fx, 0, width / 2.0], [0, fx, height / 2.0], [0, 0, 1]]
    photos = []
    for name, eye, target in VIEWS:
        R, t = look_at(eye, target)
        photos.append({"name": name, "file": f"photos/{name}.png", "hdr": f"photos/{name}.exr",
                       "K": K, "R": R, "t": t, "width": width, "height": height})
    lights = []
    for name, _, rad in LAMPS:
        poly = next(p for p in polygons if p["name"] == "light_" + name)
        strength = max(rad)
        lights.append({"name": name, "polygon": poly["vertices"], "color": [c / strength for c in rad],
                       "strength": strength, "radiance_rgb": rad})
    variants = [
        {"name": "A_off", "lights": {"A": 0}, "file": "truth/A_off.png", "hdr": "truth/A_off.exr"},
        {"name": "B_double", "lights": {"B": 2}, "file": "truth/B_double.png", "hdr": "truth/B_double.exr"},
    ]
    scene = {
        "generator": f"Relume resources/scripts/make_sample_room.py, Blender Cycles, {samples} spp, diffuse-only",
        "units": "metres", "up": "+Z", "room": ROOM, "polygons": polygons, "lights": lights,
        "photos": photos, "main_photo": "main", "variants": variants,
        "unoccluded": "truth/unoccluded.png",
        "camera_convention": "OpenCV: x_cam = R * X_world + t, x right, y down, z forward; K in pixels",
        "png_encoding": "sRGB 8-bit, Standard view transform, exposure 0",
        "exr_encoding": "linear scene radiance",
    }
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "scene.json"), "w") as f:
        json.dump(scene, f, indent=1)
    write_geometry_obj(os.path.join(out, "geometry.obj"), polygons, "# Relume sample room, metres, Z up; one group per polygon\n")
    write_colmap(out, photos, width, height, fx)
    return scene


# ---------------------------------------------------------------------------------------------
# Rendering with Blender Cycles


def setup_cycles(bpy, samples, width, height):
    """An empty scene rendered by Cycles on the CPU: diffuse light paths only, no denoising, the
    Standard view transform (the PNGs are the EXRs' sRGB encoding), a black world."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    sc = bpy.context.scene
    sc.render.engine = "CYCLES"
    sc.cycles.device = "CPU"
    sc.cycles.samples = samples
    sc.cycles.use_denoising = False
    sc.cycles.seed = 3
    sc.cycles.max_bounces = 12
    sc.cycles.diffuse_bounces = 12
    sc.cycles.glossy_bounces = 0
    sc.cycles.transmission_bounces = 0
    sc.cycles.transparent_max_bounces = 0
    sc.cycles.volume_bounces = 0
    sc.cycles.caustics_reflective = False
    sc.cycles.caustics_refractive = False
    sc.cycles.sample_clamp_indirect = 0.0
    sc.view_settings.view_transform = "Standard"
    sc.view_settings.look = "None"
    sc.view_settings.exposure = 0.0
    sc.view_settings.gamma = 1.0
    sc.render.film_transparent = False
    sc.world = bpy.data.worlds.new("black")
    sc.world.use_nodes = True
    sc.world.node_tree.nodes["Background"].inputs[1].default_value = 0.0
    sc.render.resolution_x = width
    sc.render.resolution_y = height
    sc.render.resolution_percentage = 100
    return sc


def diffuse_material(bpy, name, spec):
    """Lambertian with a procedural texture: albedo * (0.82 + 0.36 * pattern), pattern mean ~0.5,
    so the mean is ~albedo ("flat": the albedo everywhere)."""
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nt = m.node_tree
    nt.nodes.clear()
    outn = nt.nodes.new("ShaderNodeOutputMaterial")
    bsdf = nt.nodes.new("ShaderNodeBsdfDiffuse")
    alb = spec["albedo"]
    nt.links.new(bsdf.outputs["BSDF"], outn.inputs["Surface"])
    if spec["pattern"] == "flat":
        bsdf.inputs["Color"].default_value = list(alb) + [1.0]
        return m
    tex = nt.nodes.new("ShaderNodeTexCoord")
    if spec["pattern"] == "planks":
        pat = nt.nodes.new("ShaderNodeTexWave")
        pat.wave_type = "BANDS"
        pat.inputs["Scale"].default_value = 2.2
        pat.inputs["Distortion"].default_value = 3.0
        pat.inputs["Detail"].default_value = 2.0
    elif spec["pattern"] == "stripes":
        pat = nt.nodes.new("ShaderNodeTexChecker")
        pat.inputs["Scale"].default_value = 4.0
        pat.inputs["Color1"].default_value = (1, 1, 1, 1)
        pat.inputs["Color2"].default_value = (0, 0, 0, 1)
    else:
        pat = nt.nodes.new("ShaderNodeTexNoise")
        pat.inputs["Scale"].default_value = 6.0
        pat.inputs["Detail"].default_value = 4.0
    nt.links.new(tex.outputs["Object"], pat.inputs["Vector"])
    fac = pat.outputs["Fac"]
    lo = [a * 0.82 for a in alb] + [1.0]
    hi = [min(a * 1.18, 1.0) for a in alb] + [1.0]
    ramp = nt.nodes.new("ShaderNodeValToRGB")
    ramp.color_ramp.elements[0].color = lo
    ramp.color_ramp.elements[1].color = hi
    nt.links.new(fac, ramp.inputs["Fac"])
    nt.links.new(ramp.outputs["Color"], bsdf.inputs["Color"])
    return m


def add_mesh_object(bpy, sc, name, polys, material):
    """One Blender object holding `polys` (scene.json polygons), with `material`."""
    verts, faces = [], []
    for p in polys:
        base = len(verts)
        verts.extend([tuple(v) for v in p["vertices"]])
        faces.append(tuple(range(base, base + len(p["vertices"]))))
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], faces)
    mesh.update()
    obj = bpy.data.objects.new(name, mesh)
    sc.collection.objects.link(obj)
    mesh.materials.append(material)
    return obj


def add_camera(bpy, sc, ph):
    """A Blender camera for a scene.json photo (OpenCV R, t and K)."""
    import mathutils

    cd = bpy.data.cameras.new(ph["name"])
    cd.sensor_fit = "HORIZONTAL"
    cd.sensor_width = 36.0
    cd.lens = ph["K"][0][0] * 36.0 / ph["width"]
    cd.clip_start = 0.01
    cd.clip_end = 100.0
    co = bpy.data.objects.new(ph["name"], cd)
    R = ph["R"]
    t = ph["t"]
    C = [-(R[0][i] * t[0] + R[1][i] * t[1] + R[2][i] * t[2]) for i in range(3)]
    # Blender camera axes: x = cv x, y = -cv y, z = -cv z (columns of the world matrix).
    co.matrix_world = mathutils.Matrix(((R[0][0], -R[1][0], -R[2][0], C[0]),
                                        (R[0][1], -R[1][1], -R[2][1], C[1]),
                                        (R[0][2], -R[1][2], -R[2][2], C[2]),
                                        (0, 0, 0, 1)))
    sc.collection.objects.link(co)
    return co


def shoot(bpy, sc, camera, out, png, exr, tag, depth="16"):
    """Render through `camera`; the linear radiance as an EXR (half float, or "32": full float, for
    images whose highlights pass half float's 65504, such as the sun), its sRGB encoding as PNG."""
    sc.camera = camera
    bpy.ops.render.render()
    img = bpy.data.images["Render Result"]
    s = sc.render.image_settings
    s.file_format = "OPEN_EXR"
    s.color_depth = depth
    s.exr_codec = "ZIP"
    s.color_mode = "RGB"
    img.save_render(os.path.join(out, exr), scene=sc)
    s.file_format = "PNG"
    s.color_depth = "8"
    s.compression = 90
    s.color_mode = "RGB"
    img.save_render(os.path.join(out, png), scene=sc)
    print(f"[{tag}] wrote {png} and {exr}", flush=True)


def render(out, scene_desc, samples):
    import bpy

    sc = setup_cycles(bpy, samples, scene_desc["photos"][0]["width"], scene_desc["photos"][0]["height"])

    def lamp_material(name):
        m = bpy.data.materials.new(name)
        m.use_nodes = True
        nt = m.node_tree
        nt.nodes.clear()
        outn = nt.nodes.new("ShaderNodeOutputMaterial")
        emit = nt.nodes.new("ShaderNodeEmission")
        black = nt.nodes.new("ShaderNodeBsdfDiffuse")
        black.inputs["Color"].default_value = (0, 0, 0, 1)
        geo = nt.nodes.new("ShaderNodeNewGeometry")
        mix = nt.nodes.new("ShaderNodeMixShader")
        nt.links.new(geo.outputs["Backfacing"], mix.inputs["Fac"])
        nt.links.new(emit.outputs["Emission"], mix.inputs[1])
        nt.links.new(black.outputs["BSDF"], mix.inputs[2])
        nt.links.new(mix.outputs["Shader"], outn.inputs["Surface"])
        return m, emit

    mats = {k: diffuse_material(bpy, k, v) for k, v in MATERIALS.items()}
    emitters = {}
    groups = {}
    for p in scene_desc["polygons"]:
        groups.setdefault(p["group"], []).append(p)
    objects = {}
    for group, polys in groups.items():
        p0 = polys[0]
        if p0["kind"] == "light":
            m, emit = lamp_material(p0["material"])
            emitters[p0["name"][len("light_"):]] = emit
        else:
            m = mats[p0["material"]]
        objects[group] = add_mesh_object(bpy, sc, group, polys, m)

    cams = {ph["name"]: add_camera(bpy, sc, ph) for ph in scene_desc["photos"]}
    lamp_rad = {l["name"]: l["radiance_rgb"] for l in scene_desc["lights"]}

    def set_lamps(mult):
        for name, emit in emitters.items():
            r = lamp_rad[name]
            k = mult.get(name, 1.0)
            peak = max(r)
            emit.inputs["Color"].default_value = (r[0] / peak, r[1] / peak, r[2] / peak, 1)
            emit.inputs["Strength"].default_value = peak * k

    os.makedirs(os.path.join(out, "photos"), exist_ok=True)
    os.makedirs(os.path.join(out, "truth"), exist_ok=True)
    set_lamps({})
    for ph in scene_desc["photos"]:
        shoot(bpy, sc, cams[ph["name"]], out, ph["file"], ph["hdr"], "sample room")
    for v in scene_desc["variants"]:
        set_lamps(v["lights"])
        shoot(bpy, sc, cams[scene_desc["main_photo"]], out, v["file"], v["hdr"], "sample room")
    # Unoccluded: all lamps on, table and box cast no shadows.
    set_lamps({})
    for g in ("table", "box"):
        objects[g].visible_shadow = False
    shoot(bpy, sc, cams[scene_desc["main_photo"]], out, "truth/unoccluded.png", "truth/unoccluded.exr", "sample room")


def script_options(defaults):
    """The options after Blender's `--`: `--name value` for each default that is not a bool (its
    type converts the value), `--name` alone for each bool (dashes for underscores)."""
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    opts = dict(defaults)
    i = 0
    while i < len(argv):
        key = argv[i].lstrip("-").replace("-", "_")
        if key not in opts:
            sys.exit(f"unknown option {argv[i]}; known: " + ", ".join("--" + k.replace("_", "-") for k in opts))
        if isinstance(opts[key], bool):
            opts[key] = True
        else:
            opts[key] = type(opts[key])(argv[i + 1])
            i += 1
        i += 1
    return opts


def main():
    o = script_options({"out": "resources/sample_room", "samples": 256, "width": 640, "height": 480, "only_data": False})
    build_room()
    desc = write_data(o["out"], o["width"], o["height"], o["samples"])
    if not o["only_data"]:
        render(o["out"], desc, o["samples"])


if __name__ == "__main__":
    main()
