#!/usr/bin/env bash
# End-to-end: the relume command on the sample room, as a user runs it.
source "$(dirname "$0")/common.sh"

"$relume" solve "$room" --json "$tmp/solve.json" 2>"$tmp/solve.err"
check "solve exits 0" "[ $? -eq 0 ]"
check "solve prints progress" "grep -q 'refinement round' '$tmp/solve.err'"
check "solve JSON lists polygons with radiosity and irradiance" \
  "python3 -c \"import json,sys; d=json.load(open('$tmp/solve.json')); p={x['name']:x for x in d['polygons']}; \
assert p['floor']['radiosity'][0] > 0 and p['floor']['irradiance'][0] > p['floor']['radiosity'][0]; \
t=d['totals']; assert all(k in t for k in ['elements','leaves','links','rays','seconds','peak_memory_bytes'])\""

"$relume" render "$room" --camera main -o "$tmp/main.png" 2>/dev/null
check "render writes a PNG" "[ -s '$tmp/main.png' ]"
"$relume" render "$room" --camera view2 -o "$tmp/leaves.exr" --show leaves 2>/dev/null
check "render --show leaves writes an EXR" "[ -s '$tmp/leaves.exr' ]"

"$relume" render "$room" --camera nosuch -o "$tmp/x.png" 2>"$tmp/err.txt"
check "unknown camera is an error naming it" "[ $? -eq 1 ] && grep -q \"camera 'nosuch'\" '$tmp/err.txt'"
check "and writes nothing" "[ ! -e '$tmp/x.png' ]"

"$relume" solve "$tmp/nowhere" --json "$tmp/y.json" 2>"$tmp/err2.txt"
check "missing room is an error naming it" "[ $? -eq 1 ] && grep -q 'nowhere' '$tmp/err2.txt'"

"$relume" import "$room" -o "$tmp/sample.relume" 2>/dev/null
"$relume" solve "$tmp/sample.relume" --json "$tmp/proj.json" 2>/dev/null
check "a written project solves like its bundle" \
  "python3 -c \"import json; a=json.load(open('$tmp/solve.json')); b=json.load(open('$tmp/proj.json')); \
assert [p['radiosity'] for p in a['polygons']] == [p['radiosity'] for p in b['polygons']]\""

# Ctrl-C during a long solve: exit 130, no output file, no temporary left behind.
"$relume" solve "$room" --json "$tmp/cancel.json" --eps 0.0005 --min-area 0.0002 2>"$tmp/cancel.err" &
pid=$!
sleep 1.5
kill -INT $pid
wait $pid
code=$?
check "Ctrl-C cancels with exit 130" "[ $code -eq 130 ]"
check "and leaves no file" "[ -z \"\$(ls '$tmp' | grep cancel.json)\" ]"

# Relighting: preprocess into a project, relight from it, and the errors a user can make.
"$relume" preprocess "$room" -o "$tmp/lit.relume" 2>"$tmp/pre.err"
check "preprocess exits 0 and prints progress and estimates" \
  "[ $? -eq 0 ] && grep -q 'texture-based refinement' '$tmp/pre.err' && grep -q 'lamp emittances' '$tmp/pre.err'"
check "the project holds relighting data" "[ -s '$tmp/lit.relume/relight/relight.json' ]"
"$relume" relight "$tmp/lit.relume" --lamp A=0 --lamp C=1,0.8,0.6 -o "$tmp/relit.png" 2>/dev/null
check "relight writes a PNG" "[ -s '$tmp/relit.png' ]"
"$relume" relight "$tmp/lit.relume" --lamp A=0 --method ratio-only -o "$tmp/ratio.exr" 2>/dev/null
check "relight --method ratio-only writes an EXR" "[ -s '$tmp/ratio.exr' ]"
cat > "$tmp/box.json" <<'JSON'
{"virtual_objects": [{"name": "crate", "box_min": [0.7, 1.5, 0.0], "box_max": [1.1, 1.9, 0.35], "albedo": [0.6, 0.2, 0.2]}]}
JSON
"$relume" relight "$tmp/lit.relume" --virtual-object "$tmp/box.json" -o "$tmp/box.png" 2>/dev/null
check "relight with a virtual box writes a PNG" "[ -s '$tmp/box.png' ]"
"$relume" relight "$tmp/lit.relume" --lamp Z=0 -o "$tmp/bad.png" 2>"$tmp/bad.err"
check "an unknown lamp is an error naming it and the lamps there are" \
  "[ $? -eq 1 ] && grep -q \"lamp 'Z'\" '$tmp/bad.err' && grep -q 'lamps: A, B, C' '$tmp/bad.err' && [ ! -e '$tmp/bad.png' ]"
cat > "$tmp/wall.json" <<'JSON'
{"virtual_objects": [{"name": "through", "box_min": [-0.3, 1.0, 0.0], "box_max": [0.3, 1.4, 0.4], "albedo": [0.5, 0.5, 0.5]}]}
JSON
"$relume" relight "$tmp/lit.relume" --virtual-object "$tmp/wall.json" -o "$tmp/bad2.png" 2>"$tmp/bad2.err"
check "a box through a wall is an error naming both" \
  "[ $? -eq 1 ] && grep -q \"'through'\" '$tmp/bad2.err' && grep -q 'wall_left' '$tmp/bad2.err' && [ ! -e '$tmp/bad2.png' ]"
sed 's/0.6, 0.2, 0.2/1.6, 0.2, 0.2/' "$tmp/box.json" > "$tmp/albedo.json"
"$relume" relight "$tmp/lit.relume" --virtual-object "$tmp/albedo.json" -o "$tmp/bad3.png" 2>"$tmp/bad3.err"
check "an albedo above 1 is an error" "[ $? -eq 1 ] && grep -q 'albedo' '$tmp/bad3.err' && [ ! -e '$tmp/bad3.png' ]"
"$relume" relight "$tmp/sample.relume" -o "$tmp/bad4.png" 2>"$tmp/bad4.err"
check "relighting a project never preprocessed says so" "[ $? -eq 1 ] && grep -q 'relume preprocess' '$tmp/bad4.err'"

# Command-line mistakes name the option and exit 1 (docs/errors.md).
cli_error() {  # NAME EXPECTED-TEXT COMMAND...
  local name=$1 expect=$2
  shift 2
  "$relume" "$@" >/dev/null 2>"$tmp/cli.err"
  local code=$?
  check "$name" "[ $code -eq 1 ] && grep -qF -- \"$expect\" '$tmp/cli.err'"
}
cli_error "an unknown option is named" "Unknown option 'no-such-option'" solve "$room" --json "$tmp/o.json" --no-such-option
cli_error "a required option missing is named" "--json OUT.json is required" solve "$room"
cli_error "a numeric option that is not a number" "--eps" solve "$room" --json "$tmp/o.json" --eps abc
cli_error "a choice option with an unknown value" "must be bf or bfv, not 'xy'" solve "$room" --json "$tmp/o.json" --oracle xy
cli_error "a lamp scale without a value" "NAME=S" relight "$tmp/lit.relume" --lamp A -o "$tmp/o.png"
cli_error "a negative lamp scale" "finite number >= 0" relight "$tmp/lit.relume" --lamp A=-1 -o "$tmp/o.png"
cli_error "an output of the wrong type" "the output must end in .exr or .png" render "$room" --camera main -o "$tmp/o.jpg"
cli_error "images of different sizes are not compared" "the rendering 640x480" compare "$tmp/ratio.exr" "$tmp/lit.relume/relight/tex_000.orig.exr"
cli_error "a folder that is no room is named" "holds neither scene.json" check "$tmp"
cp -r "$tmp/lit.relume" "$tmp/broken.relume"
cp "$tmp/broken.relume/relight/tex_001.orig.exr" "$tmp/broken.relume/relight/tex_000.orig.exr"
cli_error "check reads a project's relighting data and names a damaged texture" \
  "tex_000.orig.exr: has the wrong size for its texture grid" check "$tmp/broken.relume"
"$relume" check "$tmp/lit.relume" >"$tmp/check.out" 2>&1
check "check says what a project holds" "[ $? -eq 0 ] && grep -q 'preprocessed (textures of photo' '$tmp/check.out'"

# Ctrl-C during preprocess leaves the existing project as it was.
cp "$tmp/lit.relume/relight/relight.json" "$tmp/before.json"
"$relume" preprocess "$room" -o "$tmp/lit.relume" --eps 0.0005 2>/dev/null &
pid=$!
sleep 2
kill -INT $pid
wait $pid
code=$?
check "Ctrl-C cancels preprocess with exit 130" "[ $code -eq 130 ]"
check "and the project is untouched" "cmp -s '$tmp/before.json' '$tmp/lit.relume/relight/relight.json' && [ -z \"\$(ls -a '$tmp' | grep saving)\" ]"

# A luminaire's photometric file, in both formats: its flux is the intensities integrated over the
# sphere (here by the trapezoid rule in Python, independently of Relume), the same from either file.
examples=$(dirname "$room")/examples
"$relume" photometry "$examples/downlight.ies" --json "$tmp/ies.json" >"$tmp/ies.out" 2>/dev/null
"$relume" photometry "$examples/downlight.ldt" --json "$tmp/ldt.json" 2>/dev/null
check "photometry gives an IES file's flux and the EULUMDAT twin's" \
  "python3 -c \"import json, math; v=open('$examples/downlight.ies').read().split('TILT=NONE')[1].split(); \
nv=int(v[3]); g=[float(x) for x in v[13:13+nv]]; I=[float(x) for x in v[14+nv:14+2*nv]]; \
flux=sum(math.pi*math.radians(g[k+1]-g[k])*(I[k]*math.sin(math.radians(g[k]))+I[k+1]*math.sin(math.radians(g[k+1]))) for k in range(nv-1)); \
a=json.load(open('$tmp/ies.json'))['flux_lm']; b=json.load(open('$tmp/ldt.json'))['flux_lm']; \
assert abs(a-flux) < 0.01*flux and abs(b-a) < 0.01*a, (a, b, flux)\" && grep -q 'light output ratio' '$tmp/ies.out'"
"$relume" relight "$tmp/lit.relume" --virtual-lamp "$examples/virtual_downlight.json" -o "$tmp/downlight.exr" 2>/dev/null
check "a virtual lamp with a photometric file relights" "[ -s '$tmp/downlight.exr' ]"
printf 'IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 3 1 1 2 0 0 0\n1 1 10\n0 45 90\n0\n100 -50 0\n' >"$tmp/bad.ies"
cli_error "a photometric file with a negative intensity is named" "bad.ies: intensity 2" photometry "$tmp/bad.ies"

# Image-based objects: a fan rendered from the example vase (few small views, to be quick), placed
# in the room and drawn into the relit image with its shadows; bad fans and places refused.
"$relume" ibr-fan "$examples/vase.obj" -o "$tmp/vase.fan" --views 24 --size 64 --rings 20,60 2>"$tmp/fan.err"
check "ibr-fan writes a fan and prints progress" "[ $? -eq 0 ] && [ -s '$tmp/vase.fan' ] && grep -q 'image fan: view' '$tmp/fan.err'"
sed 's/"position": \[[^]]*\]/"position": [0.8, 2.3, 0.0]/' "$examples/image_object.json" > "$tmp/vase.json"
"$relume" relight "$tmp/lit.relume" --lamp A=0 --lamp B=0 -o "$tmp/novase.exr" 2>/dev/null
"$relume" relight "$tmp/lit.relume" --lamp A=0 --lamp B=0 --virtual-object "$tmp/vase.json" -o "$tmp/vase.exr" 2>"$tmp/vase.err"
check "relight draws an image-based object and its shadows" \
  "[ $? -eq 0 ] && grep -q \"image-based object 'floor_vase'\" '$tmp/vase.err' && grep -Eq 'shadows on [1-9][0-9]* pixels' '$tmp/vase.err'"
"$relume" compare "$tmp/vase.exr" "$tmp/novase.exr" > "$tmp/vase_cmp.txt" 2>/dev/null
check "the image-based object changes the relit image" "awk '{exit !(\$2 < 40)}' '$tmp/vase_cmp.txt'"
head -c 3000 "$tmp/vase.fan" > "$tmp/cut.fan"
sed 's/vase.fan/cut.fan/' "$tmp/vase.json" > "$tmp/cut.json"
"$relume" relight "$tmp/lit.relume" --virtual-object "$tmp/cut.json" -o "$tmp/cut.png" 2>"$tmp/cut.err"
check "a truncated fan is an error naming it, nothing written" \
  "[ $? -eq 1 ] && grep -q 'cut.fan' '$tmp/cut.err' && grep -q 'truncated' '$tmp/cut.err' && [ ! -e '$tmp/cut.png' ]"
sed 's/"position": \[[^]]*\]/"position": [0.1, 2.3, 0.0]/' "$examples/image_object.json" > "$tmp/vase_wall.json"
cp "$tmp/vase.fan" "$tmp/vase_wall.fan" 2>/dev/null; sed -i 's/vase.fan/vase_wall.fan/' "$tmp/vase_wall.json"
"$relume" relight "$tmp/lit.relume" --virtual-object "$tmp/vase_wall.json" -o "$tmp/wall_vase.png" 2>"$tmp/wall_vase.err"
check "an image-based object through a wall is an error naming it, nothing written" \
  "[ $? -eq 1 ] && grep -q 'floor_vase' '$tmp/wall_vase.err' && grep -q 'wall_left' '$tmp/wall_vase.err' && [ ! -e '$tmp/wall_vase.png' ]"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\n' > "$tmp/nofaces.obj"
cli_error "a mesh with no faces is named, no fan written" "nofaces.obj" ibr-fan "$tmp/nofaces.obj" -o "$tmp/nofaces.fan"
check "and no fan file is left" "[ ! -e '$tmp/nofaces.fan' ]"

if [ $fail -eq 0 ]; then echo "cli: all passed"; fi
exit $fail
