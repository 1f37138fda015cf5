#!/usr/bin/env bash
# End-to-end: from the sample room's photos to a project, as a user runs it.
source "$(dirname "$0")/common.sh"

# The camera's intrinsics, as `relume calibrate` would give them (the renders carry no EXIF).
cam=$(awk '!/^#/ && NF {print $2":"$5","$6","$7","$8; exit}' "$room/colmap/cameras.txt")

# 1. COLMAP: every view registers; camera centres within 2 cm of the truth after a similarity fit.
"$relume" reconstruct "$room/photos" --out "$tmp/ws" --camera "$cam" 2>"$tmp/rec.err"
check "reconstruct exits 0" "[ $? -eq 0 ]"
check "reconstruct prints COLMAP's progress" "grep -q 'COLMAP: features' '$tmp/rec.err' && grep -q 'COLMAP: registered' '$tmp/rec.err'"
check "the model is written as text" "[ -s '$tmp/ws/sparse/cameras.txt' ] && [ -s '$tmp/ws/sparse/images.txt' ] && [ -s '$tmp/ws/sparse/points3D.txt' ]"
check "every photo registered" \
  "python3 -c \"import json; d=json.load(open('$tmp/ws/workspace.json')); assert len(d['registered']) == 7 and not d['left_out'], d\""
"$relume" align "$tmp/ws" --to "$room" --json "$tmp/align.json" -o "$tmp/aligned" >"$tmp/align.out" 2>&1
check "camera centres: median error <= 2 cm after the similarity fit" \
  "python3 -c \"import json; d=json.load(open('$tmp/align.json')); print('   median %.4f m, max %.4f m' % (d['median_m'], d['max_m'])); assert d['cameras'] == 7 and d['median_m'] <= 0.02\""

# Metric frame from a distance and the floor: three model points become z = 0, P1-P2 1.5 m apart.
ids=$(python3 -c "
import math
pts = [(l.split()[0], list(map(float, l.split()[1:4]))) for l in open('$tmp/ws/sparse/points3D.txt') if l[0] != '#']
a = pts[0]
b = max(pts, key=lambda p: math.dist(p[1], a[1]))
def off_line(p):
    u = [b[1][i] - a[1][i] for i in range(3)]; v = [p[1][i] - a[1][i] for i in range(3)]
    c = [u[1]*v[2]-u[2]*v[1], u[2]*v[0]-u[0]*v[2], u[0]*v[1]-u[1]*v[0]]
    return math.sqrt(sum(x*x for x in c))
c = max(pts, key=off_line)
print(a[0] + ',' + b[0] + ',' + c[0])")
p1=$(echo "$ids" | cut -d, -f1); p2=$(echo "$ids" | cut -d, -f2)
"$relume" align "$tmp/ws" --scale "$p1,$p2,1.5" --floor "$ids" -o "$tmp/metric" >/dev/null 2>&1
check "--scale and --floor put the points in metres on z = 0" \
  "python3 -c \"
import math
pts = {l.split()[0]: list(map(float, l.split()[1:4])) for l in open('$tmp/metric/points3D.txt') if l[0] != '#'}
a, b, c = (pts[i] for i in '$ids'.split(','))
assert abs(math.dist(a, b) - 1.5) < 1e-6 and max(abs(a[2]), abs(b[2]), abs(c[2])) < 1e-6\""

# Known cameras (here the room's true ones): COLMAP only triangulates points; poses stay put and
# the points land inside the room (4 x 5.2 x 2.6 m).
"$relume" reconstruct "$room/photos" --out "$tmp/wsk" --known-cameras "$room" 2>"$tmp/known.err"
check "reconstruct --known-cameras triangulates points with the poses unchanged" \
  "[ $? -eq 0 ] && grep -q 'triangulating points with the known cameras' '$tmp/known.err' && \
   \"$relume\" align '$tmp/wsk' --to '$room' --json '$tmp/known_align.json' >/dev/null 2>&1 && \
   python3 -c \"
import json
d = json.load(open('$tmp/known_align.json')); assert d['max_m'] < 1e-6, d
pts = [list(map(float, l.split()[1:4])) for l in open('$tmp/wsk/sparse/points3D.txt') if l[0] != '#']
inside = [p for p in pts if -0.05 < p[0] < 4.05 and -0.05 < p[1] < 5.25 and -0.05 < p[2] < 2.65]
print('   %d points, %d inside the room' % (len(pts), len(inside))); assert len(pts) > 100 and len(inside) >= 0.95 * len(pts)\""

# 2. Polygons from clicks (resources/sample_room/clicks.json) with the room's cameras.
"$relume" triangulate "$room/colmap" --clicks "$room/clicks.json" -o "$tmp/tri.relume" 2>"$tmp/tri.err"
check "triangulate writes a project" "[ $? -eq 0 ] && [ -s '$tmp/tri.relume/project.json' ] && [ -s '$tmp/tri.relume/triangulation.json' ]"
check "the project keeps the clicks it was made from (same points, same polygons)" \
  "python3 -c \"
import json
a, b = json.load(open('$room/clicks.json')), json.load(open('$tmp/tri.relume/clicks.json'))
assert a['points'] == b['points'], 'points differ'
assert [p['name'] for p in a['polygons']] == [p['name'] for p in b['polygons']]
assert [p['corners'] for p in a['polygons']] == [p['corners'] for p in b['polygons']]
assert [bool(p.get('lamp')) for p in a['polygons']] == [bool(p.get('lamp')) for p in b['polygons']]
\""
check "its corners lie within 5 mm of the true ones (median), 3 cm at worst" \
  "python3 -c \"
import json, math
t = {p['name']: p['vertices'] for p in json.load(open('$room/scene.json'))['polygons']}
e = sorted(min(math.dist(a, b) for b in p['vertices'])
           for p in json.load(open('$tmp/tri.relume/project.json'))['polygons'] for a in t[p['name']])
print('   corner error median %.4f m, largest %.4f m' % (e[len(e) // 2], e[-1])); assert e[len(e) // 2] < 0.005 and e[-1] < 0.03\""
check "a point clicked in photos from nearly one direction is flagged" "grep -q 'depth is weak' '$tmp/tri.err'"
"$relume" solve "$tmp/tri.relume" --json "$tmp/tri_solve.json" 2>/dev/null
check "relume solve accepts the triangulated project" "[ $? -eq 0 ] && [ -s '$tmp/tri_solve.json' ]"
"$relume" evaluate "$room" --out "$tmp/ev_true" >/dev/null 2>&1
"$relume" evaluate "$room" --geometry "$tmp/tri.relume" --out "$tmp/ev_tri" >/dev/null 2>"$tmp/ev_tri.err"
check "with --geometry the truth is the bundle's: each lamp's exitance and each polygon's albedo" \
  "python3 -c \"
import json, math, re
scene = json.load(open('$room/scene.json'))
lamps = {l['name']: math.pi * sum(l['radiance_rgb']) / 3 for l in scene['lights']}
seen = re.findall(r'lamp (\\S+)\\s+exitance [0-9.]+, truth ([0-9.]+)', open('$tmp/ev_tri.err').read())
print('   lamps: ' + ', '.join('%s truth %s (bundle %.1f)' % (n, t, lamps[n]) for n, t in seen))
assert sorted(n for n, _ in seen) == sorted(lamps), seen
assert all(abs(float(t) - lamps[n]) <= 0.05 + 1e-3 * lamps[n] for n, t in seen)
albedo = {p['name']: p.get('albedo') for p in scene['polygons']}
rows = json.load(open('$tmp/ev_tri/report.json'))['reflectances']
assert rows and all(max(abs(a - b) for a, b in zip(r['truth'], albedo[r['polygon']])) < 1e-9 for r in rows), rows[:3]
\""
check "the triangulated room relights within 1 dB of the true geometry" \
  "python3 -c \"
import json
a = {v['name']: v['full'] for v in json.load(open('$tmp/ev_true/report.json'))['variants']}
b = {v['name']: v['full'] for v in json.load(open('$tmp/ev_tri/report.json'))['variants']}
for n in a:
    for m in ('psnr_all', 'psnr_shadow'):
        print('   %s %s: true geometry %.2f dB, triangulated %.2f dB' % (n, m, a[n][m], b[n][m]))
        assert b[n][m] >= a[n][m] - 1.0
\""

# 2b. The paper's own workflow without COLMAP: the cameras solved from the clicks alone (known
# focal length), the metric frame from four of the clicked corners also measured with a tape.
python3 - "$room" "$tmp/clicks_cp.json" <<'PY'
import json, sys
room, out = sys.argv[1], sys.argv[2]
scene = json.load(open(room + '/scene.json'))
names = {}
for p in scene['polygons']:
    for v in p['vertices']:
        names.setdefault(tuple(round(x, 6) for x in v), 'p%d' % len(names))
where = {n: k for k, n in names.items()}
c = json.load(open(room + '/clicks.json'))
measured = [n for n in sorted(c['points'], key=lambda n: int(n[1:])) if 'xyz' not in c['points'][n]]
for n in measured[:2] + measured[-2:]:
    c['points'][n]['xyz'] = [round(x / 0.005) * 0.005 for x in where[n]]
json.dump(c, open(out, 'w'))
PY
mkdir -p "$tmp/nomodel"
focal=$(echo "$cam" | cut -d: -f2 | cut -d, -f1)
"$relume" triangulate "$tmp/nomodel" --photos "$room/photos" --clicks "$tmp/clicks_cp.json" --focal "$focal" \
  -o "$tmp/calib.relume" 2>"$tmp/calib.err"
check "cameras solved from clicks alone, metric frame from control points" \
  "[ $? -eq 0 ] && grep -q 'cameras solved from' '$tmp/calib.err' && grep -q 'control points' '$tmp/calib.err'"
check "their centres lie within 2 cm of the true cameras, the corners within 1 cm (median)" \
  "python3 -c \"
import json, math
def centre(p):
    R, t = p['R'], p['t']
    return [-sum(R[k][r] * t[k] for k in range(3)) for r in range(3)]
truth = json.load(open('$room/scene.json'))
tc = {p['name']: centre(p) for p in truth['photos']}
proj = json.load(open('$tmp/calib.relume/project.json'))
errs = [math.dist(centre(p), tc[p['name']]) for p in proj['photos']]
t = {p['name']: p['vertices'] for p in truth['polygons']}
e = sorted(min(math.dist(a, b) for b in p['vertices']) for p in proj['polygons'] for a in t[p['name']])
print('   %d cameras, largest centre error %.4f m; corner error median %.4f m' % (len(errs), max(errs), e[len(e) // 2]))
assert len(errs) == 7 and max(errs) < 0.02 and e[len(e) // 2] < 0.01\""

# 3. Errors, each naming what is wrong.
cat > "$tmp/collinear.json" <<'JSON'
{"points": {"a": {"xyz": [0, 0, 0]}, "b": {"xyz": [1, 1, 0]}, "c": {"xyz": [2, 2, 0]}},
 "polygons": [{"name": "shelf", "corners": ["a", "b", "c"]}]}
JSON
"$relume" triangulate "$room/colmap" --clicks "$tmp/collinear.json" -o "$tmp/bad.relume" 2>"$tmp/e1"
check "collinear picked points: error naming the polygon" \
  "[ $? -eq 1 ] && grep -q 'collinear' '$tmp/e1' && grep -q 'shelf' '$tmp/e1' && [ ! -e '$tmp/bad.relume' ]"
cat > "$tmp/behind.json" <<'JSON'
{"points": {"p": {"main": [630.5, 240.5], "view0": [10.5, 240.5]}},
 "polygons": [{"name": "odd", "corners": ["p", {"xyz": [1, 1, 0]}, {"xyz": [2, 1, 0]}]}]}
JSON
"$relume" triangulate "$room/colmap" --clicks "$tmp/behind.json" -o "$tmp/bad.relume" 2>"$tmp/e2"
check "a point behind a camera: error naming point and photo" \
  "[ $? -eq 1 ] && grep -q 'behind the camera' '$tmp/e2' && grep -q 'point p' '$tmp/e2'"
RELUME_COLMAP=relume-no-such-colmap "$relume" reconstruct "$room/photos" --out "$tmp/ws2" 2>"$tmp/e3"
check "colmap missing: error saying how to install it" "[ $? -eq 1 ] && grep -q 'apt-get install colmap' '$tmp/e3'"
mkdir -p "$tmp/cut"; cp "$room/photos/main.png" "$room/photos/view0.png" "$tmp/cut/"
head -c 3000 "$room/photos/view1.png" > "$tmp/cut/view1.png"
"$relume" reconstruct "$tmp/cut" --out "$tmp/ws3" 2>"$tmp/e4"
check "a truncated photo: error naming it" "[ $? -eq 1 ] && grep -q 'view1.png' '$tmp/e4'"
"$relume" calibrate "$room/photos" --pattern 9x6 --square 0.025 -o "$tmp/intr.json" 2>"$tmp/e5"
check "no checkerboard: error naming the photos" "[ $? -eq 1 ] && grep -q 'checkerboard' '$tmp/e5' && grep -q 'main.png' '$tmp/e5' && [ ! -e '$tmp/intr.json' ]"

# Ctrl-C while COLMAP runs: exit 130, COLMAP's process killed, no model written.
"$relume" reconstruct "$room/photos" --out "$tmp/ws_cancel" 2>/dev/null &
pid=$!
sleep 1
kill -INT $pid
wait $pid
code=$?
sleep 0.5
check "Ctrl-C cancels reconstruct with exit 130" "[ $code -eq 130 ]"
check "and kills COLMAP, writing no model" \
  "! pgrep -f 'colmap .*ws_cancel' >/dev/null && [ ! -e '$tmp/ws_cancel/sparse/cameras.txt' ]"

# 4. HDR merge of a bracket made from the linear photo (three exposures two stops apart).
for e in 0.25 1 4; do oiiotool "$room/photos/main.exr" --mulc $e --colorconvert linear sRGB -d uint8 -o "$tmp/b_$e.png"; done
"$relume" hdr-merge "$tmp/b_0.25.png" "$tmp/b_1.png" "$tmp/b_4.png" --times 1/4,1,4 -o "$tmp/merged.exr" --response "$tmp/resp.csv" 2>/dev/null
check "hdr-merge writes the radiance image and the response" "[ $? -eq 0 ] && [ -s '$tmp/merged.exr' ] && [ $(wc -l < "$tmp/resp.csv" 2>/dev/null || echo 0) -eq 257 ]"
"$relume" hdr-merge "$tmp/b_0.25.png" "$tmp/b_1.png" -o "$tmp/m2.exr" 2>"$tmp/e6"
check "no exposure times anywhere: error naming the file" "[ $? -eq 1 ] && grep -q 'b_0.25.png' '$tmp/e6' && grep -q -- '--times' '$tmp/e6'"

if [ $fail -eq 0 ]; then echo "reconstruct cli: all passed"; fi
exit $fail
