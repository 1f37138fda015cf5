#!/usr/bin/env python3
"""Re-render a ground-truth bundle from its own description with Blender Cycles, so that its
images follow from its scene.json exactly (flat albedos, its lamps with `two_sided`, its cameras):
every photo, every variant's truth image and truth/unoccluded. A method evaluated on the copy is
judged against physics alone; on the original, also against whatever the bundle's generator did
that its description does not say.

    python3 resources/scripts/rerender_bundle.py BUNDLE OUT [--samples 96] [--no-shadow table,crate]
        [--blender blender] [--half]

OUT gets a copy of BUNDLE with photos/NAME.exr and .png and truth/VARIANT.exr and .png replaced
(PNG: sRGB 8-bit of the EXR, exposure 0, as the bundles' png_encoding says). Takes about half a
minute per image at 640 x 480 on two cores. With --half the EXR files are stored as half floats
(zip), a third of the size (the renders' noise is far above half's precision).

resources/sample_room_flat was made so:

    python3 resources/scripts/rerender_bundle.py resources/sample_room resources/sample_room_flat \
        --samples 128 --no-shadow table,box --half
"""
import argparse
import json
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def render(blender, bundle, out, extra):
    cmd = [blender, "-b", "--python", os.path.join(HERE, "render_bundle.py"), "--", bundle, out, "--percent", "100"] + extra
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if r.returncode != 0 or not os.path.exists(out):
        sys.exit("rerender_bundle.py: %s failed:\n%s" % (" ".join(cmd), r.stdout[-2000:]))


def to_png(exr, png):
    r = subprocess.run(["oiiotool", exr, "--ch", "R,G,B", "--tocolorspace", "sRGB", "-d", "uint8", "-o", png],
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if r.returncode != 0:
        sys.exit("rerender_bundle.py: oiiotool could not write %s: %s" % (png, r.stdout))


def to_half(exr):
    tmp = exr + ".half.exr"
    r = subprocess.run(["oiiotool", exr, "--ch", "R,G,B", "-d", "half", "--compression", "zip", "-o", tmp],
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if r.returncode != 0:
        sys.exit("rerender_bundle.py: oiiotool could not convert %s: %s" % (exr, r.stdout))
    os.replace(tmp, exr)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("bundle")
    ap.add_argument("out")
    ap.add_argument("--samples", type=int, default=96)
    ap.add_argument("--no-shadow", default="table,crate", help="groups casting no shadow in truth/unoccluded")
    ap.add_argument("--blender", default="blender")
    ap.add_argument("--half", action="store_true", help="store the EXR files as half floats")
    a = ap.parse_args()
    with open(os.path.join(a.bundle, "scene.json")) as f:
        desc = json.load(f)
    if os.path.exists(a.out):
        sys.exit("rerender_bundle.py: %s exists; give a new folder" % a.out)
    shutil.copytree(a.bundle, a.out)
    for root, dirs, files in os.walk(a.out):
        for n in dirs + files:
            os.chmod(os.path.join(root, n), 0o755 if n in dirs else 0o644)
    samples = ["--samples", str(a.samples)]
    jobs = []
    for ph in desc["photos"]:
        jobs.append((ph["hdr"], ph["file"], ["--camera", ph["name"]]))
    for v in desc.get("variants", []):
        if "hdr" in v:
            jobs.append((v["hdr"], v["file"], ["--variant", v["name"]]))
    if os.path.exists(os.path.join(a.bundle, "truth", "unoccluded.exr")):
        jobs.append(("truth/unoccluded.exr", "truth/unoccluded.png", ["--no-shadow", a.no_shadow]))
    for i, (hdr, png, extra) in enumerate(jobs):
        print("rerender_bundle.py: [%d/%d] %s" % (i + 1, len(jobs), hdr), file=sys.stderr, flush=True)
        exr = os.path.join(a.out, hdr)
        render(a.blender, a.out, exr, samples + extra)
        if a.half:
            to_half(exr)
        to_png(exr, os.path.join(a.out, png))
    seed7 = os.path.join(a.out, "photos", "main_seed7.exr")
    if os.path.exists(seed7):
        os.remove(seed7)  # another sampling seed of the old main photo: not of this one


if __name__ == "__main__":
    main()
