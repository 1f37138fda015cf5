#!/usr/bin/env python3
"""The ablation table of a ground-truth room: `relume evaluate` with each part of the estimation
switched off in turn, so that the causes of an error can be told apart.

    python3 scripts/ablate.py BUNDLE [--out DIR] [--relume build/app/cli/relume]

Rows: as shipped; the engine's BF oracle instead of BFV (links refined by the kernel's spread
alone, blind to what hides part of them); the paper's estimate (no inverse global illumination); no shared materials
for unseen polygons; every lamp taken as one-sided (a copy of the bundle without `two_sided`,
when it has two-sided lamps); the bundle's true lamps instead of the estimates; and the scene
oracle (true lamps and true polygon albedos as the engine's reflectances: what is left is
rendering error — the engine's, and the bundle's own where its images do not follow from its
description). Columns: the lamp-off variants' PSNR on the all and
shadow masks (worst .. best), `virtual_light_only`, the unoccluded image on the shadow mask, and
each lamp's power error against the bundle's truth (computed here from its scene.json; power per
unit area, so that a lamp taken as one-sided is judged by the light it gives).
Writes DIR/ablation.md and DIR/ablation.json and prints the table.
"""
import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))


def lamp_truth(scene):
    """Each lamp's true power per unit area (grey): pi x its radiance, x 2 for a two-sided lamp."""
    out = {}
    for l in scene.get("lights", scene.get("lamps", [])):
        if "radiance_rgb" in l:
            rgb = l["radiance_rgb"]
        else:
            rgb = [c * l["strength"] for c in l["color"]]
        out[l["name"]] = math.pi * sum(rgb) / 3 * (2 if l.get("two_sided") else 1)
    return out


def lamp_off_variants(scene):
    """Variants that switch a lamp off (a scale of 0)."""
    names = []
    for v in scene.get("variants", []):
        for s in v.get("lights", {}).values():
            if (s == 0) or (isinstance(s, list) and not any(s)):
                names.append(v["name"])
                break
    return names


def evaluate(relume, bundle, out, args):
    os.makedirs(out, exist_ok=True)
    cmd = [relume, "evaluate", bundle, "--out", out] + args
    with open(os.path.join(out, "evaluate.log"), "w") as log:
        rc = subprocess.run(cmd, stdout=log, stderr=subprocess.STDOUT).returncode
    if rc != 0:
        sys.exit("ablate: %s failed (exit %d), see %s" % (" ".join(cmd), rc, os.path.join(out, "evaluate.log")))
    with open(os.path.join(out, "report.json")) as f:
        return json.load(f)


def span(values):
    return "%.2f .. %.2f" % (min(values), max(values)) if values else "—"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("bundle")
    ap.add_argument("--out", default=None)
    ap.add_argument("--relume", default=os.path.join(ROOT, "build", "app", "cli", "relume"))
    a = ap.parse_args()
    bundle = os.path.abspath(a.bundle)
    with open(os.path.join(bundle, "scene.json")) as f:
        scene = json.load(f)
    out = os.path.abspath(a.out or os.path.join("ablation", os.path.basename(bundle.rstrip("/"))))
    truth = lamp_truth(scene)
    off = lamp_off_variants(scene)
    rows = [("as shipped", bundle, []),
            ("BF oracle (refinement blind to visibility)", bundle, ["--oracle", "bf"]),
            ("paper's estimate (no inverse GI)", bundle, ["--no-inverse-gi"]),
            ("no shared materials", bundle, ["--no-shared-materials"])]
    tmp = None
    lamps = scene.get("lights", scene.get("lamps", []))
    if any(l.get("two_sided") for l in lamps):
        # A copy of the bundle whose lamps are all one-sided (a copy, not links: a bundle may not
        # name files through links that lead out of it).
        tmp = tempfile.mkdtemp(prefix="relume_ablate_")
        copy = os.path.join(tmp, os.path.basename(bundle.rstrip("/")))
        shutil.copytree(bundle, copy)
        one = json.loads(json.dumps(scene))
        for l in one.get("lights", one.get("lamps", [])):
            l.pop("two_sided", None)
        with open(os.path.join(copy, "scene.json"), "w") as f:
            json.dump(one, f, indent=1)
        rows.append(("lamps one-sided", copy, []))
    rows.append(("oracle lamps (the reflectances still estimated)", bundle, ["--oracle-lamps"]))
    rows.append(("oracle scene (true lamps and albedos: rendering error only)", bundle, ["--oracle-lamps", "--oracle-albedos"]))
    table = []
    try:
        for name, where, args in rows:
            print("ablate: %s ..." % name, file=sys.stderr, flush=True)
            r = evaluate(a.relume, where, os.path.join(out, name.split(" (")[0].replace(" ", "_").replace("'", "")), args)
            v = {x["name"]: x for x in r["variants"]}
            # Power per unit area: a lamp estimated as two-sided emits its exitance from each face.
            used = {l["name"]: sum(l["used"]) / 3 * (2 if l.get("two_sided") else 1) for l in r["estimates"]["lamps"]}
            errors = {n: 100 * (used[n] / truth[n] - 1) for n in used if n in truth and truth[n] > 0}
            row = {
                "ablation": name,
                "lamp_off_all": [v[n]["full"]["psnr_all"] for n in off if n in v],
                "lamp_off_shadow": [v[n]["full"]["psnr_shadow"] for n in off if n in v],
                "virtual_light_only_all": v["virtual_light_only"]["full"]["psnr_all"] if "virtual_light_only" in v else None,
                "unoccluded_shadow": r["unoccluded"]["full"]["psnr_shadow"],
                "lamp_error_percent": errors,
            }
            table.append(row)
    finally:
        if tmp:
            shutil.rmtree(tmp, ignore_errors=True)
    lines = ["# Ablation: %s" % os.path.basename(bundle.rstrip("/")), "",
             "Lamp-off variants: %s. PSNR in dB (comparison protocol), lamp errors in %% of the truth." % ", ".join(off), "",
             "| ablation | lamp-off, all | lamp-off, shadow | virtual_light_only, all | unoccluded, shadow | lamp errors |",
             "| --- | --- | --- | --- | --- | --- |"]
    for row in table:
        vlo = row["virtual_light_only_all"]
        errs = ", ".join("%s %+.1f" % (n, e) for n, e in sorted(row["lamp_error_percent"].items()))
        lines.append("| %s | %s | %s | %s | %.2f | %s |" % (row["ablation"], span(row["lamp_off_all"]), span(row["lamp_off_shadow"]),
                                                          "—" if vlo is None else "%.2f" % vlo, row["unoccluded_shadow"], errs))
    text = "\n".join(lines) + "\n"
    with open(os.path.join(out, "ablation.md"), "w") as f:
        f.write(text)
    with open(os.path.join(out, "ablation.json"), "w") as f:
        json.dump(table, f, indent=1)
    print(text)


if __name__ == "__main__":
    main()
