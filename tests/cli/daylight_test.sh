#!/usr/bin/env bash
# End-to-end: daylight on the project's own daylight sample room, as a user runs it — a
# time-varying sky played back from a folder of fisheyes (one frame per image), the room kept as a
# project with its daylight session (opened without solving again), lamps and virtual lamps beside
# the daylight, and bad skies refused with nothing written.
source "$(dirname "$0")/common.sh"

cat > "$tmp/box.json" <<'JSON'
{"virtual_objects": [{"name": "box", "box_min": [2.1, 1.95, 0.0], "box_max": [2.45, 2.3, 0.35], "albedo": [0.8, 0.38, 0.06]}]}
JSON
mkdir "$tmp/skies"
cp "$room/sky/fisheye_sun1.exr" "$tmp/skies/t1.exr"
cp "$room/sky/fisheye_sun2.exr" "$tmp/skies/t2.exr"
"$relume" relight "$room" --sky "$tmp/skies" --daylight volume --virtual-object "$tmp/box.json" -o "$tmp/frames" 2>"$tmp/play.err"
check "a folder of skies plays back (exit 0)" "[ $? -eq 0 ]"
check "one linear and one display image per sky, and frames.json" \
  "[ -s '$tmp/frames/t1.exr' ] && [ -s '$tmp/frames/t1.png' ] && [ -s '$tmp/frames/t2.exr' ] && [ -s '$tmp/frames/t2.png' ] && [ -s '$tmp/frames/frames.json' ]"
check "a progress line per frame" "[ \$(grep -c '^frame [12]/2' '$tmp/play.err') -eq 2 ]"
check "frames.json lists the frames in name order, each with its sun (48 and 22 degrees up)" \
  "python3 -c \"import json,math; d=json.load(open('$tmp/frames/frames.json')); f=d['frames']; \
assert [x['image'] for x in f] == ['t1.png', 't2.png']; \
e=[math.degrees(math.asin(x['sun_direction'][2])) for x in f]; assert abs(e[0]-48) < 1.5 and abs(e[1]-22) < 1.5, e; \
assert d['render_ms_median'] > 0\""
check "the two suns give two different images" "! cmp -s '$tmp/frames/t1.exr' '$tmp/frames/t2.exr'"
check "no half-written folder left" "[ ! -e '$tmp/frames.partial' ]"

# The room kept as a project with its daylight session: relit from it, nothing is estimated or
# solved again, and the frames are those of the bundle (solved on the spot above).
"$relume" daylight-basis "$room" -o "$tmp/proj" >"$tmp/keep.out" 2>"$tmp/keep.err"
check "daylight-basis -o writes a project that keeps the daylight session" \
  "[ $? -eq 0 ] && [ -s '$tmp/proj/project.json' ] && [ -s '$tmp/proj/daylight/solution.bin' ] && grep -q '65 basis solutions' '$tmp/keep.out'"
"$relume" daylight-basis "$room" -o "$tmp/proj2" --grid 8 2>"$tmp/keepgrid.err"
check "daylight-basis -o with a report option is refused before anything is solved" \
  "[ $? -eq 1 ] && grep -q 'takes no other option' '$tmp/keepgrid.err' && [ ! -e '$tmp/proj2' ]"
"$relume" preprocess "$room" -o "$tmp/proj2" --mean-reflectance 0.5 2>"$tmp/prepday.err"
check "preprocess on a daylight room is the daylight session (a lamp-path option is refused, naming it)" \
  "[ $? -eq 1 ] && grep -q 'mean-reflectance' '$tmp/prepday.err' && grep -q 'daylight' '$tmp/prepday.err' && [ ! -e '$tmp/proj2' ]"
cp -r "$tmp/frames" "$tmp/bundleframes"
"$relume" relight "$tmp/proj" --sky "$tmp/skies" --daylight volume --virtual-object "$tmp/box.json" -o "$tmp/frames/" 2>"$tmp/again.err"
check "an earlier run's frames are replaced (the output given with a trailing slash)" "[ $? -eq 0 ] && [ -s '$tmp/frames/t2.png' ] && [ ! -e '$tmp/frames.partial' ]"
check "the project's kept session is opened, not solved again" "grep -q \"opened the project's kept daylight solution\" '$tmp/again.err'"
for f in t1 t2; do
  oiiotool "$tmp/frames/$f.exr" "$tmp/bundleframes/$f.exr" --absdiff --printstats >"$tmp/kept_$f.stats" 2>&1
  check "frame $f from the kept session is the bundle's (no pixel off by more than 0.002)" \
    "python3 -c \"import re; t=open('$tmp/kept_$f.stats').read(); \
mx=[float(v) for v in re.search(r'Stats Max: ([-0-9.e]+) ([-0-9.e]+) ([-0-9.e]+)', t).groups()]; assert max(mx) < 0.002, mx\""
done
mkdir "$tmp/mine"
echo "the user's own notes" > "$tmp/mine/notes.txt"
"$relume" relight "$tmp/proj" --sky "$tmp/skies" -o "$tmp/mine" 2>"$tmp/mine.err"
check "a folder of other files is refused and left alone" \
  "[ $? -eq 1 ] && grep -q 'holds other files' '$tmp/mine.err' && [ \"\$(ls '$tmp/mine')\" = notes.txt ]"

mkdir "$tmp/bad"
cp "$room/sky/fisheye_sun1.exr" "$tmp/bad/t1.exr"
printf 'not an image' > "$tmp/bad/t0.exr"
"$relume" relight "$tmp/proj" --sky "$tmp/bad" -o "$tmp/badframes" 2>"$tmp/bad.err"
check "a broken sky in the folder is an error naming it" "[ $? -eq 1 ] && grep -q 't0.exr' '$tmp/bad.err'"
check "and nothing is written" "[ ! -e '$tmp/badframes' ] && [ ! -e '$tmp/badframes.partial' ]"

mkdir "$tmp/empty"
"$relume" relight "$tmp/proj" --sky "$tmp/empty" -o "$tmp/emptyframes" 2>"$tmp/empty.err"
check "a folder with no sky image is an error saying so" "[ $? -eq 1 ] && grep -q 'no HDR sky image' '$tmp/empty.err'"

# A lamp beside the daylight: a copy of the room with a 20 cm panel 3 cm below the ceiling, facing
# down, switched on under the photos' own sky (near-field): every pixel of the room can only gain
# light over the photo (taken with the lamp off), and the room as a whole gains some.
cp -r "$room" "$tmp/lamproom"
python3 - "$tmp/lamproom/scene.json" <<'PY'
import json, sys
f = sys.argv[1]
s = json.load(open(f))
z = s["room"][2] - 0.03
x, y, a = 1.2, 1.6, 0.1
s["polygons"].append({"name": "lamp_L", "group": "lamp_L", "kind": "light", "material": "lamp", "albedo": [0, 0, 0],
                      "vertices": [[x - a, y - a, z], [x - a, y + a, z], [x + a, y + a, z], [x + a, y - a, z]]})
s["lights"].append({"name": "L", "polygon": s["polygons"][-1]["vertices"], "radiance_rgb": [60.0, 55.0, 45.0]})
json.dump(s, open(f, "w"))
PY
"$relume" relight "$tmp/lamproom" --sky sun0 --lamp L=1 -o "$tmp/lamp_on.exr" 2>"$tmp/lamp.err"
check "a lamp switched on beside the daylight renders (exit 0)" "[ $? -eq 0 ] && [ -s '$tmp/lamp_on.exr' ]"
oiiotool "$tmp/lamp_on.exr" "$room/photos/main.exr" --sub --printstats >"$tmp/lamp.stats" 2>&1
check "with the lamp on no pixel is darker than the photo, and the room gains light" \
  "python3 -c \"import re; t=open('$tmp/lamp.stats').read(); \
mn=[float(v) for v in re.search(r'Stats Min: ([-0-9.e]+) ([-0-9.e]+) ([-0-9.e]+)', t).groups()]; \
av=[float(v) for v in re.search(r'Stats Avg: ([-0-9.e]+) ([-0-9.e]+) ([-0-9.e]+)', t).groups()]; \
assert min(mn) > -1e-4, mn; assert min(av) > 1e-3, av\""
# The same panel as a virtual lamp in the room as it is: the same light, within 3 % of what the
# lamp adds (the scene's lamp sits in the hierarchy from the start, the virtual one joins it).
python3 - "$tmp/lamproom/scene.json" "$tmp/vlamp.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
json.dump({"virtual_lights": [{"name": "V", "polygon": s["polygons"][-1]["vertices"], "radiance_rgb": [60.0, 55.0, 45.0]}]},
          open(sys.argv[2], "w"))
PY
"$relume" relight "$tmp/proj" --sky sun0 --virtual-lamp "$tmp/vlamp.json" -o "$tmp/vlamp_on.exr" 2>"$tmp/vlamp.err"
check "a virtual lamp beside the daylight renders (exit 0)" "[ $? -eq 0 ] && [ -s '$tmp/vlamp_on.exr' ]"
oiiotool "$tmp/vlamp_on.exr" "$tmp/lamp_on.exr" --absdiff --printstats >"$tmp/vlamp.stats" 2>&1
check "the virtual lamp lights the room as the same lamp in the model does" \
  "python3 -c \"import re; d=open('$tmp/vlamp.stats').read(); t=open('$tmp/lamp.stats').read(); \
dv=[float(v) for v in re.search(r'Stats Avg: ([-0-9.e]+) ([-0-9.e]+) ([-0-9.e]+)', d).groups()]; \
av=[float(v) for v in re.search(r'Stats Avg: ([-0-9.e]+) ([-0-9.e]+) ([-0-9.e]+)', t).groups()]; \
assert all(x < 0.03 * y for x, y in zip(dv, av)), (dv, av)\""
"$relume" relight "$tmp/proj" --sky sun0 --virtual-lamp "$tmp/vlamp.json" --daylight volume -o "$tmp/x.png" 2>"$tmp/vlampv.err"
check "a virtual lamp on the volume path is refused, saying which method takes it" "[ $? -eq 1 ] && grep -q 'near-field' '$tmp/vlampv.err'"
# A --virtual-object file's lamps are taken as well (as the lamp path takes them), where daylight
# can light them: on the volume path the lamp beside the box is left out, saying which method
# takes it, and the box is drawn.
python3 - "$tmp/box.json" "$tmp/vlamp.json" "$tmp/boxlamp.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1])); d.update(json.load(open(sys.argv[2])))
json.dump(d, open(sys.argv[3], "w"))
PY
"$relume" relight "$tmp/proj" --sky sun0 --virtual-object "$tmp/boxlamp.json" --daylight volume -o "$tmp/boxlamp.png" 2>"$tmp/boxlampv.err"
check "a virtual-object file's lamp on the volume path is left out with a warning naming the method, the box drawn" \
  "[ $? -eq 0 ] && [ -s '$tmp/boxlamp.png' ] && grep -q 'warning: left out: .*near-field' '$tmp/boxlampv.err'"
# One file given with both options must list both: asked for objects, it is refused when it has none.
"$relume" relight "$tmp/proj" --sky sun0 --virtual-lamp "$tmp/vlamp.json" --virtual-object "$tmp/vlamp.json" -o "$tmp/x.png" 2>"$tmp/both.err"
check "a file given with --virtual-lamp and --virtual-object that lists no object is refused" \
  "[ $? -eq 1 ] && grep -q 'lists no virtual object' '$tmp/both.err'"
# A photometric lamp beside the box is not lit under daylight: the box is drawn, the lamp left
# out with a warning naming it (asked for with --virtual-lamp, the same lamp is an error).
python3 - "$tmp/box.json" "$(dirname "$0")/../../resources/examples/virtual_downlight.json" "$tmp/boxies.json" <<'PY'
import json, os, sys
d = json.load(open(sys.argv[1])); l = json.load(open(sys.argv[2]))
for v in l["virtual_lights"]: v["photometry"] = os.path.join(os.path.dirname(sys.argv[2]), v["photometry"])
d.update(l); json.dump(d, open(sys.argv[3], "w"))
PY
"$relume" relight "$tmp/proj" --sky sun0 --virtual-object "$tmp/boxies.json" --daylight volume -o "$tmp/boxies.png" 2>"$tmp/boxies.err"
check "a virtual-object file's photometric lamp is left out with a warning, its box drawn" \
  "[ $? -eq 0 ] && [ -s '$tmp/boxies.png' ] && grep -q 'warning: left out: .*downlight' '$tmp/boxies.err'"
# An image-based object under daylight (its fan made by ibr-fan): drawn with its shadow by the
# volume and near-field methods, lit by the window's samples, the sun and the irradiance volume;
# the distant method and a lamp switched on are refused, naming the object's file.
"$relume" ibr-fan "$(dirname "$0")/../../resources/examples/vase.obj" -o "$tmp/vase.fan" --views 24 --size 96 --rings 20,50 2>/dev/null
echo '{"virtual_objects": [{"name": "sun_vase", "fan": "vase.fan", "position": [2.3, 2.1, 0.0]}]}' > "$tmp/vase.json"
"$relume" relight "$tmp/proj" --sky sun0 --daylight volume --virtual-object "$tmp/vase.json" -o "$tmp/vase.exr" 2>"$tmp/vase.err"
check "an image-based object is drawn under daylight with its shadow" \
  "[ $? -eq 0 ] && [ -s '$tmp/vase.exr' ] && grep -Eq \"image-based object 'sun_vase': fan view [0-9]+, [1-9][0-9]+ pixels, shadows on [1-9][0-9]+ pixels\" '$tmp/vase.err'"
"$relume" relight "$tmp/proj" --sky sun0 --daylight volume -o "$tmp/novase.exr" 2>/dev/null
check "and it changes the image" "! cmp -s '$tmp/vase.exr' '$tmp/novase.exr'"
"$relume" relight "$tmp/proj" --sky sun0 --daylight distant --virtual-object "$tmp/vase.json" -o "$tmp/x.png" 2>"$tmp/vased.err"
check "an image-based object with the distant method is refused, naming its fan" \
  "[ $? -eq 1 ] && grep -q 'vase.fan' '$tmp/vased.err' && grep -q 'volume or near-field' '$tmp/vased.err'"
"$relume" relight "$tmp/lamproom" --sky sun0 --lamp L=1 --daylight distant -o "$tmp/x.png" 2>"$tmp/lampd.err"
check "a lamp with the distant method (the sky alone) is refused" "[ $? -eq 1 ] && grep -q 'sky at infinity alone' '$tmp/lampd.err'"
"$relume" relight "$tmp/lamproom" --sky sun0 --lamp L=1 --daylight volume --virtual-object "$tmp/box.json" -o "$tmp/x.png" 2>"$tmp/lampv.err"
check "a lamp with virtual objects on the volume path is refused" "[ $? -eq 1 ] && grep -q 'daylight only' '$tmp/lampv.err'"
python3 - "$tmp/vlamp.json" "$tmp/vase.json" "$tmp/lampvase.json" "$tmp/box.json" "$tmp/boxvase.json" <<'PY'
import json, sys
l = json.load(open(sys.argv[1])); v = json.load(open(sys.argv[2])); b = json.load(open(sys.argv[4]))
l["virtual_objects"] = v["virtual_objects"]; json.dump(l, open(sys.argv[3], "w"))
beside = json.loads(json.dumps(v["virtual_objects"])); beside[0]["position"] = [2.8, 2.1, 0.0]
b["virtual_objects"] += beside; json.dump(b, open(sys.argv[5], "w"))
PY
"$relume" relight "$tmp/proj" --sky sun0 --daylight near-field --virtual-lamp "$tmp/lampvase.json" -o "$tmp/lampvase.png" 2>"$tmp/lampvase2.err"
check "an image-based object beside an asked virtual lamp is left out with a warning, the lamp lit" \
  "[ $? -eq 0 ] && [ -s '$tmp/lampvase.png' ] && grep -q \"warning: left out: .*sun_vase.*daylight only\" '$tmp/lampvase2.err'"
"$relume" relight "$tmp/proj" --sky sun0 --daylight volume --virtual-object "$tmp/boxvase.json" -o "$tmp/boxvase.png" 2>"$tmp/boxvase.err"
check "a box and an image-based object beside it are drawn together under daylight" \
  "[ $? -eq 0 ] && [ -s '$tmp/boxvase.png' ] && grep -Eq \"image-based object 'sun_vase': fan view [0-9]+, [1-9][0-9]+ pixels\" '$tmp/boxvase.err'"
"$relume" relight "$tmp/lamproom" --sky sun0 --lamp L=1 --daylight near-field --virtual-object "$tmp/vase.json" -o "$tmp/x.png" 2>"$tmp/lampvase.err"
check "an image-based object with a lamp on is refused: lit by daylight only" "[ $? -eq 1 ] && grep -q 'daylight only' '$tmp/lampvase.err'"
"$relume" relight "$tmp/proj" --sky sun0 --lamp Q=1 -o "$tmp/x.png" 2>"$tmp/lampq.err"
check "a lamp the room does not have is an error naming it" "[ $? -eq 1 ] && grep -q \"lamp 'Q'\" '$tmp/lampq.err'"
check "and no image is written by any of them" "[ ! -e '$tmp/x.png' ]"

# The sky camera's lens: its image circle found from the dark border (Blender's fisheye: centred,
# filling the 256 x 256 image), the same sun as the lens described in words; a calibrated lens of
# another image size refused naming it; a circle that cannot be found refused.
"$relume" sky "$room/sky/fisheye_sun0.exr" --circle auto >"$tmp/circle.out" 2>"$tmp/circle.err"
check "sky --circle auto finds Blender's circle (centre 128, 128, radius 128 within half a pixel)" \
  "[ $? -eq 0 ] && python3 -c \"import re; m=re.search(r'image circle: centre ([0-9.]+), ([0-9.]+), radius ([0-9.]+)', open('$tmp/circle.out').read()); \
assert m and all(abs(float(x) - 128) < 0.5 for x in m.groups()), m\""
"$relume" sky "$room/sky/fisheye_sun0.exr" >"$tmp/nocircle.out" 2>/dev/null
check "and the sun it gives is the described lens's (within 0.1 degree)" \
  "python3 -c \"import re; e=[float(re.search(r'sun: elevation ([0-9.]+)', open(f).read()).group(1)) for f in ('$tmp/circle.out', '$tmp/nocircle.out')]; \
assert abs(e[0] - e[1]) < 0.1, e\""
cat > "$tmp/lens.json" <<'JSON'
{"model": "OPENCV_FISHEYE", "width": 640, "height": 480, "fx": 190, "fy": 190, "cx": 320, "cy": 240, "k1": 0.02, "k2": 0, "k3": 0, "k4": 0}
JSON
# A calibrated lens that is the ideal equidistant 180-degree projection of the 256 x 256 fisheye
# (f = 128 / (pi / 2), no distortion) relights the room as the ideal projection does.
python3 -c "import json, math; json.dump({'model': 'OPENCV_FISHEYE', 'width': 256, 'height': 256, 'fx': 256 / math.pi, \
'fy': 256 / math.pi, 'cx': 128, 'cy': 128, 'k1': 0, 'k2': 0, 'k3': 0, 'k4': 0}, open('$tmp/ideal_lens.json', 'w'))"
"$relume" relight "$tmp/proj" --sky "$room/sky/fisheye_sun1.exr" --lens "$tmp/ideal_lens.json" -o "$tmp/lens_sun1.exr" 2>"$tmp/lensrel.err"
"$relume" relight "$tmp/proj" --sky "$room/sky/fisheye_sun1.exr" -o "$tmp/ideal_sun1.exr" 2>/dev/null
check "a fisheye read through a calibrated lens equal to the ideal projection relights the room alike (PSNR over 50 dB)" \
  "[ -s '$tmp/lens_sun1.exr' ] && \"$relume\" compare '$tmp/lens_sun1.exr' '$tmp/ideal_sun1.exr' 2>/dev/null | python3 -c \"import re,sys; t=sys.stdin.read(); \
m=re.search(r'([0-9.]+) dB', t); assert m and float(m.group(1)) > 50, t\""
"$relume" sky "$room/sky/fisheye_sun0.exr" --lens "$tmp/ideal_lens.json" >"$tmp/lenssky.out" 2>/dev/null
check "sky FISHEYE --lens (the ideal projection as a calibrated lens) finds the sun where the ideal lens does" \
  "python3 -c \"import re; e=[float(re.search(r'sun: elevation ([0-9.]+)', open(f).read()).group(1)) for f in ('$tmp/lenssky.out', '$tmp/nocircle.out')]; \
assert abs(e[0] - e[1]) < 0.05, e\""
# A room whose sky names its calibrated lens (inline; the words give only the orientation).
mkdir -p "$tmp/lensroom" && cp -r "$room/." "$tmp/lensroom/"
python3 - "$tmp/lensroom/scene.json" "$tmp/ideal_lens.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1])); lens = json.load(open(sys.argv[2]))
for c in s["daylight"]["sky"]:
    c["fisheye_lens"] = lens
    c["fisheye_model"] = "looking up (+Z), image up = +Y"
json.dump(s, open(sys.argv[1], "w"))
PY
"$relume" sky "$tmp/lensroom" >"$tmp/lensroom.out" 2>"$tmp/lensroom.err"
check "sky ROOM reads the room's sky through the lens it names (the sun as through the ideal lens)" \
  "[ $? -eq 0 ] && python3 -c \"import re; e=[float(re.search(r'sun: elevation ([0-9.]+)', open(f).read()).group(1)) for f in ('$tmp/lensroom.out', '$tmp/nocircle.out')]; \
assert abs(e[0] - e[1]) < 0.05, e\""
"$relume" sky "$tmp/lensroom" --lens "$tmp/ideal_lens.json" 2>"$tmp/lensroom2.err"
check "sky ROOM --lens is refused: a room's sky takes the lens its daylight section names" "[ $? -eq 1 ] && grep -q 'takes the lens its daylight section names' '$tmp/lensroom2.err'"
"$relume" sky "$room/sky/fisheye_sun0.exr" --lens "$tmp/lens.json" 2>"$tmp/lens.err"
check "a calibrated lens of another image size is refused, naming the lens file" \
  "[ $? -eq 1 ] && grep -q 'lens.json' '$tmp/lens.err' && grep -q '640x480' '$tmp/lens.err'"
oiiotool "$room/sky/fisheye_sun0.exr" --fill:color=1,1,1 256x256+0+0 -o "$tmp/white.exr"
"$relume" sky "$tmp/white.exr" --circle auto 2>"$tmp/white.err"
check "an image lit to its corners has no circle to find: refused, naming it and what to give" \
  "[ $? -eq 1 ] && grep -q 'white.exr' '$tmp/white.err' && grep -q -- '--circle CX,CY,R' '$tmp/white.err'"

exit $fail
