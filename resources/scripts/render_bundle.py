"""Render a ground-truth bundle's documented scene with Blender Cycles, to check a bundle.

A bundle's photos and truth images are meant to follow from its scene.json: its polygons, their
albedos (the means of whatever texture they carry), its lamps (radiance_rgb, two_sided) and its
cameras. This script rebuilds exactly that scene — flat albedos, Lambertian emitters, an
unbiased path tracer (every diffuse bounce, no clamping) — and renders one photo's view, with the
lamps of a variant if asked. The ratio of two such renders (a variant over the photo) does not
depend on the textures, so it can be compared with the ratio of the bundle's own images: where
they disagree, the bundle's renders do not follow from its description, and no method that
starts from that description can match them.

    blender -b --python resources/scripts/render_bundle.py -- BUNDLE OUT.exr
        [--camera main] [--variant NAME] [--samples 64] [--percent 50]
        [--diffuse-bounces 12] [--clamp-indirect 0] [--no-shadow GROUP,...] [--seed 0]

A variant's multipliers, new lamps (virtual_lights) and new boxes (virtual_objects) are rendered
with it.

On the sample room (resources/sample_room), lamp A off over the photo, per image region, agrees
with the bundle's truth to about 1 %.
"""
import argparse
import json
import os
import sys


def parse():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    ap = argparse.ArgumentParser(prog="render_bundle.py")
    ap.add_argument("bundle")
    ap.add_argument("out")
    ap.add_argument("--camera", default=None, help="photo name (default: the bundle's main photo)")
    ap.add_argument("--variant", default=None, help="a variant's lamp multipliers")
    ap.add_argument("--samples", type=int, default=64)
    ap.add_argument("--percent", type=int, default=50, help="resolution, percent of the photo's")
    ap.add_argument("--diffuse-bounces", type=int, default=12)
    ap.add_argument("--clamp-indirect", type=float, default=0.0, help="Cycles' indirect clamp (0: none)")
    ap.add_argument("--seed", type=int, default=0, help="Cycles' sampling seed (two seeds: the render's own noise)")
    ap.add_argument("--no-shadow", default="", help="groups whose polygons cast no shadows, comma-separated "
                    "(truth/unoccluded: --no-shadow table,crate)")
    return ap.parse_args(argv)


def main():
    import bpy
    import mathutils

    a = parse()
    with open(os.path.join(a.bundle, "scene.json")) as f:
        desc = json.load(f)
    mult = {}
    if a.variant:
        found = [v for v in desc.get("variants", []) if v["name"] == a.variant]
        if not found:
            sys.exit("render_bundle.py: %s has no variant %s" % (a.bundle, a.variant))
        mult = found[0].get("lights", {})
        variant = found[0]
    else:
        variant = {}
    camera_name = a.camera or desc.get("main_photo", "main")
    if isinstance(camera_name, dict):
        camera_name = camera_name.get("name", "main")
    photos = [p for p in desc["photos"] if p["name"] == camera_name]
    if not photos:
        sys.exit("render_bundle.py: %s has no photo %s" % (a.bundle, camera_name))
    photo = photos[0]

    bpy.ops.wm.read_factory_settings(use_empty=True)
    sc = bpy.context.scene
    sc.render.engine = "CYCLES"
    sc.cycles.device = "CPU"
    sc.cycles.samples = a.samples
    sc.cycles.seed = a.seed
    sc.cycles.use_denoising = False
    sc.cycles.max_bounces = max(12, a.diffuse_bounces)
    sc.cycles.diffuse_bounces = a.diffuse_bounces
    sc.cycles.glossy_bounces = 0
    sc.cycles.transmission_bounces = 0
    sc.cycles.sample_clamp_indirect = a.clamp_indirect
    sc.view_settings.view_transform = "Standard"
    sc.world = bpy.data.worlds.new("black")
    sc.world.use_nodes = True
    sc.world.node_tree.nodes["Background"].inputs[1].default_value = 0.0
    sc.render.resolution_x = photo["width"]
    sc.render.resolution_y = photo["height"]
    sc.render.resolution_percentage = a.percent

    lamps_by_polygon = {}
    for lamp in desc.get("lights", []):
        key = json.dumps(lamp["polygon"]) if isinstance(lamp["polygon"], list) else lamp["polygon"]
        lamps_by_polygon[key] = lamp

    def material(poly):
        m = bpy.data.materials.new(poly["name"])
        m.use_nodes = True
        nt = m.node_tree
        nt.nodes.clear()
        out = nt.nodes.new("ShaderNodeOutputMaterial")
        lamp = lamps_by_polygon.get(poly["name"]) or lamps_by_polygon.get(json.dumps(poly["vertices"]))
        if poly.get("kind") == "light" and lamp is None:
            for l in desc.get("lights", []):
                if poly["name"].endswith("_" + l["name"]):
                    lamp = l
        if lamp is None:
            bsdf = nt.nodes.new("ShaderNodeBsdfDiffuse")
            r, g, b = poly.get("albedo", [0.5, 0.5, 0.5])
            bsdf.inputs["Color"].default_value = (r, g, b, 1)
            nt.links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
            return m
        rad = lamp["radiance_rgb"]
        peak = max(max(rad), 1e-12)
        emit = nt.nodes.new("ShaderNodeEmission")
        emit.inputs["Color"].default_value = (rad[0] / peak, rad[1] / peak, rad[2] / peak, 1)
        emit.inputs["Strength"].default_value = peak * float(mult.get(lamp["name"], 1.0))
        if lamp.get("two_sided", False):
            nt.links.new(emit.outputs["Emission"], out.inputs["Surface"])
            return m
        # One-sided: the back face is black.
        black = nt.nodes.new("ShaderNodeBsdfDiffuse")
        black.inputs["Color"].default_value = (0, 0, 0, 1)
        geo = nt.nodes.new("ShaderNodeNewGeometry")
        mix = nt.nodes.new("ShaderNodeMixShader")
        nt.links.new(geo.outputs["Backfacing"], mix.inputs["Fac"])
        nt.links.new(emit.outputs["Emission"], mix.inputs[1])
        nt.links.new(black.outputs["BSDF"], mix.inputs[2])
        nt.links.new(mix.outputs["Shader"], out.inputs["Surface"])
        return m

    # A variant's new lamps (emissive quads, one-sided unless they say two_sided) and new boxes
    # (axis-aligned, standing where box_min/box_max say, flat albedo).
    polys = list(desc["polygons"])
    no_shadow = set(g for g in a.no_shadow.split(",") if g)
    for v in variant.get("virtual_lights", []):
        lamps_by_polygon[v["name"]] = v
        polys.append({"name": v["name"], "kind": "light", "vertices": v["polygon"]})
    for v in variant.get("virtual_objects", []):
        if "box_min" not in v:
            sys.exit("render_bundle.py: virtual object %s is not a box" % v.get("name", "?"))
        lo, hi = v["box_min"], v["box_max"]
        corner = lambda i, j, k: (hi[0] if i else lo[0], hi[1] if j else lo[1], hi[2] if k else lo[2])
        faces = {"top": [(0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)], "bottom": [(0, 0, 0), (0, 1, 0), (1, 1, 0), (1, 0, 0)],
                 "front": [(0, 0, 0), (1, 0, 0), (1, 0, 1), (0, 0, 1)], "back": [(0, 1, 0), (0, 1, 1), (1, 1, 1), (1, 1, 0)],
                 "left": [(0, 0, 0), (0, 0, 1), (0, 1, 1), (0, 1, 0)], "right": [(1, 0, 0), (1, 1, 0), (1, 1, 1), (1, 0, 1)]}
        for f, cs in faces.items():
            polys.append({"name": "%s_%s" % (v.get("name", "box"), f), "kind": "real",
                          "vertices": [corner(*c) for c in cs], "albedo": v["albedo"]})

    for poly in polys:
        if poly.get("kind") == "window":
            continue  # an opening: nothing there
        verts = [tuple(v) for v in poly["vertices"]]
        mesh = bpy.data.meshes.new(poly["name"])
        mesh.from_pydata(verts, [], [tuple(range(len(verts)))])
        mesh.update()
        obj = bpy.data.objects.new(poly["name"], mesh)
        if poly.get("group") in no_shadow:
            obj.visible_shadow = False
        sc.collection.objects.link(obj)
        mesh.materials.append(material(poly))

    # The photo's camera (OpenCV: x_cam = R X + t; Blender's camera looks down its -z, y up).
    cd = bpy.data.cameras.new(camera_name)
    cd.sensor_fit = "HORIZONTAL"
    cd.sensor_width = 36.0
    cd.lens = photo["K"][0][0] * 36.0 / photo["width"]
    cd.clip_start = 0.01
    cd.clip_end = 1000.0
    cam = bpy.data.objects.new(camera_name, cd)
    R, t = photo["R"], photo["t"]
    C = [-(R[0][i] * t[0] + R[1][i] * t[1] + R[2][i] * t[2]) for i in range(3)]
    cam.matrix_world = mathutils.Matrix(((R[0][0], -R[1][0], -R[2][0], C[0]),
                                         (R[0][1], -R[1][1], -R[2][1], C[1]),
                                         (R[0][2], -R[1][2], -R[2][2], C[2]),
                                         (0, 0, 0, 1)))
    sc.collection.objects.link(cam)
    sc.camera = cam
    bpy.ops.render.render()
    s = sc.render.image_settings
    s.file_format = "OPEN_EXR"
    s.color_depth = "32"
    s.color_mode = "RGB"
    bpy.data.images["Render Result"].save_render(a.out, scene=sc)
    print("wrote", a.out)


if __name__ == "__main__":
    main()
