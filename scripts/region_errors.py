#!/usr/bin/env python3
"""Where a relit image's error sits: `relume evaluate`'s renderings against a bundle's truth, on a
grid of image blocks, by the comparison protocol's steps (4x4 box, lamp pixels left out, one gain
per channel fitted over the image); per block its share of the squared error and its mean
relative error, then the whole image's PSNR (peak: the truth's 99.9th percentile).

    python3 scripts/region_errors.py BUNDLE EVALUATE_OUT [VARIANT ...] [--grid 4]

Needs numpy and OpenImageIO's Python bindings (Debian: python3-numpy python3-openimageio; run
with /usr/bin/python3). A diagnostic for people, not a test: nothing in CI runs it.
"""
import argparse
import os

import numpy as np
import OpenImageIO as oiio


def read(path):
    buf = oiio.ImageBuf(path)
    if buf.has_error:
        raise SystemExit("%s: %s" % (path, buf.geterror()))
    return buf.get_pixels(oiio.FLOAT)[..., :3]


def box4(a):
    h, w = a.shape[0] // 4 * 4, a.shape[1] // 4 * 4
    return a[:h, :w].reshape(h // 4, 4, w // 4, 4, 3).mean(axis=(1, 3))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("bundle")
    ap.add_argument("evaluate_out")
    ap.add_argument("variants", nargs="*")
    ap.add_argument("--grid", type=int, default=4)
    a = ap.parse_args()
    variants = a.variants or sorted(f[:-len(".full.exr")] for f in os.listdir(a.evaluate_out) if f.endswith(".full.exr")
                                    and f != "original.full.exr")
    photo = box4(read(os.path.join(a.bundle, "photos", "main.exr")))
    lum = photo.mean(-1)
    keep = lum <= 20 * np.median(lum)
    n = a.grid
    for v in variants:
        truth = box4(read(os.path.join(a.bundle, "truth", v + ".exr")))
        full = box4(read(os.path.join(a.evaluate_out, v + ".full.exr")))
        gain = np.array([(full[..., c][keep] * truth[..., c][keep]).sum() / (full[..., c][keep] ** 2).sum() for c in range(3)])
        err = (full * gain - truth).mean(-1)
        rel = err / np.maximum(truth.mean(-1), 1e-6)
        se = np.where(keep, err ** 2, 0.0)
        peak = np.percentile(truth.mean(-1)[keep], 99.9)
        print("%s: gain %s; per block (rows top to bottom): share of the squared error, mean relative error" % (v, np.round(gain, 3)))
        H, W = err.shape
        for i in range(n):
            cells = []
            for j in range(n):
                rs, cs = slice(i * H // n, (i + 1) * H // n), slice(j * W // n, (j + 1) * W // n)
                k = keep[rs, cs]
                cells.append("%5.1f%% %+5.1f%%" % (100 * se[rs, cs].sum() / se.sum(), 100 * rel[rs, cs][k].mean() if k.any() else 0))
            print("   " + "   ".join(cells))
        print("   PSNR over the image: %.2f dB" % (10 * np.log10(peak ** 2 / (se.sum() / keep.sum()))))


if __name__ == "__main__":
    main()
