"""Writes the seed corpora under tests/fuzz/corpus/ from the sample room (valid files, small).

    python3 tests/fuzz/make_corpus.py [PREPROCESSED_PROJECT]

PREPROCESSED_PROJECT (e.g. from `relume preprocess resources/sample_room -o P`) gives the relight
harness its seed: the project's project.json with its relight/relight.json.

Each seed is one fuzz input in the harnesses' layout (split.h): two little-endian 16-bit lengths,
then the files one after another.
"""
import json
import os
import struct
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
SAMPLE = os.path.join(ROOT, "resources", "sample_room")
COLMAP = os.path.join(SAMPLE, "colmap")
MODEL_IDS = {"SIMPLE_PINHOLE": 0, "PINHOLE": 1, "SIMPLE_RADIAL": 2, "RADIAL": 3, "OPENCV": 4}


def pack(a, b, c=b""):
    return struct.pack("<HH", len(a), len(b)) + a + b + c


def write(name, seed, data):
    folder = os.path.join(HERE, "corpus", name)
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, seed), "wb") as f:
        f.write(data)


def lines(path):
    with open(path) as f:
        return [l.rstrip("\n") for l in f if not l.startswith("#")]


def main():
    cams = open(os.path.join(COLMAP, "cameras.txt"), "rb").read()
    ims = open(os.path.join(COLMAP, "images.txt"), "rb").read()
    points = (b"1 1.0 2.0 0.5 200 180 160 0.4 1 0 2 0\n"
              b"2 1.5 2.5 0.7 10 20 30 0.2 1 1 3 1\n")
    ims_with_points = ims.replace(b"main.png\n\n", b"main.png\n100.5 200.5 1 300.0 220.0 2\n", 1)
    write("colmap_text", "sample_room", pack(cams, ims))
    write("colmap_text", "with_points", pack(cams, ims_with_points, points))
    # The same model in COLMAP's binary layout.
    cb = b""
    cam_lines = [l.split() for l in lines(os.path.join(COLMAP, "cameras.txt")) if l.strip()]
    cb += struct.pack("<Q", len(cam_lines))
    for c in cam_lines:
        cb += struct.pack("<IiQQ", int(c[0]), MODEL_IDS[c[1]], int(c[2]), int(c[3]))
        cb += b"".join(struct.pack("<d", float(v)) for v in c[4:])
    im_lines = [l.split() for l in lines(os.path.join(COLMAP, "images.txt")) if l.strip()]
    ib = struct.pack("<Q", len(im_lines))
    for n, i in enumerate(im_lines):
        ib += struct.pack("<I", int(i[0])) + b"".join(struct.pack("<d", float(v)) for v in i[1:8])
        ib += struct.pack("<I", int(i[8])) + i[9].encode() + b"\0"
        pts = [(100.5, 200.5, 1), (300.0, 220.0, 2)] if n == 0 else []
        ib += struct.pack("<Q", len(pts))
        for x, y, pid in pts:
            ib += struct.pack("<ddQ", x, y, pid)
    pb = struct.pack("<Q", 2)
    for pid, xyz, rgb, err, track in [(1, (1.0, 2.0, 0.5), (200, 180, 160), 0.4, [(1, 0)]),
                                      (2, (1.5, 2.5, 0.7), (10, 20, 30), 0.2, [(1, 1)])]:
        pb += struct.pack("<Q", pid) + struct.pack("<ddd", *xyz) + bytes(rgb) + struct.pack("<d", err)
        pb += struct.pack("<Q", len(track)) + b"".join(struct.pack("<II", a, b) for a, b in track)
    write("colmap_binary", "sample_room", pack(cb, ib))
    write("colmap_binary", "with_points", pack(cb, ib, pb))
    rooms()
    if len(sys.argv) > 1:
        proj = sys.argv[1]
        write("relight", "sample_room", pack(open(os.path.join(proj, "project.json"), "rb").read(),
                                             open(os.path.join(proj, "relight", "relight.json"), "rb").read()))


BOX_OBJ = b"o box\nv 1 1 0\nv 2 1 0\nv 2 2 0\nv 1 2 0\nv 1 1 1\nv 2 1 1\nv 2 2 1\nv 1 2 1\n" \
          b"f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n"


def compact(obj):
    return json.dumps(obj, separators=(",", ":")).encode()


def rooms():
    scene_bytes = open(os.path.join(SAMPLE, "scene.json"), "rb").read()
    scene = json.loads(scene_bytes)
    obj = open(os.path.join(SAMPLE, "geometry.obj"), "rb").read()
    # Bundles: geometry in scene.json; geometry from geometry.obj (scene.json keeps the names,
    # kinds and albedos); a variant whose virtual object is an OBJ file.
    write("bundle", "sample_room", pack(compact(scene), obj))
    meta = dict(scene)
    meta["polygons"] = [{k: v for k, v in p.items() if k != "vertices"} for p in scene["polygons"]]
    write("bundle", "geometry_obj", pack(compact(meta), obj))
    with_mesh = dict(scene)
    with_mesh["variants"] = scene.get("variants", [])[:1] + [
        {"name": "mesh", "virtual_objects": [{"name": "box", "obj": "box.obj", "albedo": [0.6, 0.5, 0.4]}]}]
    write("bundle", "virtual_mesh", pack(compact(with_mesh), obj, BOX_OBJ))
    daylight = dict(scene)
    daylight["variants"] = [{"name": "noon", "sun": "noon"}]
    daylight["daylight"] = {"photos_sun": "morning", "sky": [
        {"name": "morning", "fisheye": "sky/morning.exr",
         "fisheye_model": "equidistant, 180 deg, looking up (+Z), image up = +Y", "fisheye_position": [2.0, 2.5, 2.7],
         "panorama": "sky/pano.exr", "panorama_position": [4.5, 2.5, 1.5]},
        {"name": "noon", "fisheye": "sky/noon.exr", "fisheye_model": "equisolid, 180 deg, looking up, image up = -Y"}]}
    write("bundle", "daylight", pack(compact(daylight), obj))
    # The OBJ room with its JSON: materials by the OBJ's usemtl names.
    materials = {}
    for p in scene["polygons"]:
        if p.get("material") and p.get("albedo"):
            materials[p["material"]] = p["albedo"]
    side = {k: v for k, v in scene.items() if k != "polygons"}
    side["materials"] = materials
    write("obj_json", "sample_room", pack(obj, compact(side)))
    write("obj_json", "virtual_mesh", pack(obj, compact(dict(side, variants=with_mesh["variants"])), BOX_OBJ))
    # Lighting changes, as `relume relight` reads them.
    for name in ("virtual_box", "virtual_lamp", "image_object"):
        write("variant", name, pack(open(os.path.join(ROOT, "resources", "examples", name + ".json"), "rb").read(), b""))
    write("variant", "mesh", pack(compact({"name": "mesh", "lights": {"A": 0.5}, "virtual_objects": [
        {"name": "box", "obj": "box.obj", "albedo": [0.6, 0.5, 0.4]}]}), BOX_OBJ))
    write("intrinsics", "calibrated", compact({"width": 640, "height": 480, "model": "OPENCV", "fx": 512.3, "fy": 511.9,
                                               "cx": 320.4, "cy": 239.8, "k1": -0.12, "k2": 0.03, "p1": 0.001,
                                               "p2": -0.0005, "rms_pixels": 0.21}))
    write("fisheye_lens", "calibrated", compact({"width": 640, "height": 480, "model": "OPENCV_FISHEYE", "fx": 190.05,
                                                 "fy": 190.05, "cx": 322.33, "cy": 238.11, "k1": 0.0193, "k2": -0.0158,
                                                 "k3": 0.0058, "k4": -0.0017, "rms_pixels": 0.112,
                                                 "circle": {"cx": 320.0, "cy": 240.0, "radius": 231.5}}))
    write("fisheye_lens", "ideal", compact({"width": 256, "height": 256, "model": "OPENCV_FISHEYE", "fx": 81.487,
                                            "fy": 81.487, "cx": 128, "cy": 128}))
    write("sky_description", "day101", b"\xff\xff" + b"equidistant, 180 deg, looking up (+Z), image up = +Y")
    write("sky_description", "equisolid", b"\x63\x4f" + b"Equisolid 150 deg, looking up, image up = -X")
    write("workspace", "reconstructed", compact({"photos": "/home/user/room/photos", "registered": ["main", "view0"],
                                                 "left_out": ["blurry"], "points": 5321, "metric": True,
                                                 "seconds": {"features": 4.2, "matching": 1.1, "mapping": 9.8}}))
    photometry_seeds()
    mesh_seeds()


def photometry_seeds():
    """A downlight of cosine shape (I = 800 cd x cos gamma, 2513 lm) in both photometric formats, and an
    IES file with its tilt data included and a C-dependent distribution."""
    import math
    gammas = list(range(0, 95, 15))
    cos = [round(800 * math.cos(math.radians(g)), 2) for g in gammas]
    ies = ["IESNA:LM-63-2002", "[TEST] Relume fuzz seed", "[LUMINAIRE] cosine downlight", "TILT=NONE",
           "1 -1 1 %d 1 1 2 0.3 0.3 0" % len(gammas), "1 1 40", " ".join(map(str, gammas)), "0",
           " ".join(map(str, cos))]
    write("ies", "cosine", ("\n".join(ies) + "\n").encode())
    cs = [0, 45, 90]
    tilted = ["IESNA:LM-63-1995", "[LUMINAIRE] quadrants", "TILT=INCLUDE", "1", "3", "0 45 90", "1 0.95 0.9",
              "2 1200 1.5 %d %d 1 2 0.3 1.2 0.1" % (len(gammas), len(cs)), "0.95 1 60", " ".join(map(str, gammas)),
              " ".join(map(str, cs))]
    for c in cs:
        tilted.append(" ".join(str(round(v * (1 + 0.3 * math.cos(math.radians(2 * c))), 2)) for v in cos))
    write("ies", "tilt_quadrants", ("\r\n".join(tilted) + "\r\n").encode())
    ldt = ["Relume fuzz seed", "1", "1", "1", "0", str(len(gammas) * 2 - 1), "15", "report", "cosine downlight", "1",
           "cosine.ldt", "2026-12-02"] + ["100"] * 9 + ["100", "100", "1", "0", "1", "1", "LED", "2513", "3000", "90",
                                                        "20"] + ["0,5"] * 10 + ["0"]
    ldt += [str(g) for g in range(0, 181, 15)]
    ldt += [str(round(800 * max(0.0, math.cos(math.radians(g))) * 1000 / 2513, 3)) for g in range(0, 181, 15)]
    write("ldt", "cosine", ("\r\n".join(ldt) + "\r\n").encode())


def mesh_seeds():
    """Meshes for image-based objects: the first byte picks OBJ ('0') or PLY ('1'). The fan seeds
    (corpus/fan) are fans of a tetrahedron written by relume itself:
    relume ibr-fan tet.obj -o tetrahedron.fan --views 3 --size 8 --rings 30, and
    relume ibr-fan tet.obj -o two_rings_plain.fan --views 4 --size 12 --rings 10,70 --no-dither."""
    write("mesh", "obj_quad", b"0mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nusemtl red\n"
          b"f 1//1 2//1 3//1 4//1\nf -4 -2 -1\n")
    write("mesh", "ply_ascii", b"1ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
          b"property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nelement face 1\n"
          b"property list uchar int vertex_indices\nend_header\n0 0 0 255 0 0\n1 0 0 0 255 0\n0 1 0 0 0 255\n3 0 1 2\n")
    for order, name in (("<", "binary_little_endian"), (">", "binary_big_endian")):
        hdr = ("ply\nformat %s 1.0\ncomment seed\nelement vertex 3\nproperty float x\nproperty float y\n"
               "property float z\nproperty float nx\nproperty float ny\nproperty float nz\nelement face 1\n"
               "property list uchar int vertex_indices\nelement extra 1\nproperty list uchar float stuff\n"
               "property double w\nend_header\n" % name).encode()
        body = b"".join(struct.pack(order + "6f", *v) for v in [(0, 0, 0, 0, 0, 1), (1, 0, 0, 0, 0, 1), (0, 1, 0, 0, 0, 1)])
        body += struct.pack(order + "B3i", 3, 0, 1, 2) + struct.pack(order + "B2fd", 2, 1.0, 2.0, 3.0)
        write("mesh", "ply_binary" if order == "<" else "ply_big_endian", b"1" + hdr + body)
    # glTF: one quad, as JSON with a base64 buffer and as GLB ('2' picks the format).
    buf = struct.pack("<12f", 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0) + struct.pack("<12f", *([0, 0, 1] * 4))
    buf += struct.pack("<6H", 0, 1, 2, 0, 2, 3)
    def gltf(buffer):
        return compact({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
                        "nodes": [{"children": [1], "rotation": [0, 0.7071, 0, 0.7071]}, {"mesh": 0, "scale": [2, 2, 2]}],
                        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2, "material": 0}]}],
                        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.1, 0.05, 1]}}],
                        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3"},
                                      {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
                                      {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}],
                        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                                        {"buffer": 0, "byteOffset": 48, "byteLength": 48},
                                        {"buffer": 0, "byteOffset": 96, "byteLength": 12}],
                        "buffers": [dict({"byteLength": len(buf)}, **buffer)]})
    import base64
    write("mesh", "gltf_base64", b"2" + gltf({"uri": "data:application/octet-stream;base64," + base64.b64encode(buf).decode()}))
    chunk = gltf({})
    chunk += b" " * (-len(chunk) % 4)
    binary = buf + b"\0" * (-len(buf) % 4)
    glb = b"glTF" + struct.pack("<2I", 2, 12 + 8 + len(chunk) + 8 + len(binary))
    glb += struct.pack("<2I", len(chunk), 0x4E4F534A) + chunk + struct.pack("<2I", len(binary), 0x004E4942) + binary
    write("mesh", "glb", b"2" + glb)


if __name__ == "__main__":
    main()
