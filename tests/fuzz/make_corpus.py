"""Writes the seed corpora under tests/fuzz/corpus/ from the sample room (valid files, small).

    python3 tests/fuzz/make_corpus.py

Each seed is one fuzz input in the harnesses' layout (split.h): two little-endian 16-bit lengths,
then the files one after another.
"""
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
COLMAP = os.path.join(ROOT, "resources", "sample_room", "colmap")
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


if __name__ == "__main__":
    main()
