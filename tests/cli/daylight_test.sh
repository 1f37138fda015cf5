#!/usr/bin/env bash
# End-to-end: daylight on the project's own daylight sample room, as a user runs it — a
# time-varying sky played back from a folder of fisheyes (one frame per image), and bad skies
# refused with nothing written.
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

"$relume" relight "$room" --sky "$tmp/skies" --daylight volume -o "$tmp/frames/" 2>"$tmp/again.err"
check "an earlier run's frames are replaced (the output given with a trailing slash)" "[ $? -eq 0 ] && [ -s '$tmp/frames/t2.png' ] && [ ! -e '$tmp/frames.partial' ]"
mkdir "$tmp/mine"
echo "the user's own notes" > "$tmp/mine/notes.txt"
"$relume" relight "$room" --sky "$tmp/skies" -o "$tmp/mine" 2>"$tmp/mine.err"
check "a folder of other files is refused and left alone" \
  "[ $? -eq 1 ] && grep -q 'holds other files' '$tmp/mine.err' && [ \"\$(ls '$tmp/mine')\" = notes.txt ]"

mkdir "$tmp/bad"
cp "$room/sky/fisheye_sun1.exr" "$tmp/bad/t1.exr"
printf 'not an image' > "$tmp/bad/t0.exr"
"$relume" relight "$room" --sky "$tmp/bad" -o "$tmp/badframes" 2>"$tmp/bad.err"
check "a broken sky in the folder is an error naming it" "[ $? -eq 1 ] && grep -q 't0.exr' '$tmp/bad.err'"
check "and nothing is written" "[ ! -e '$tmp/badframes' ] && [ ! -e '$tmp/badframes.partial' ]"

mkdir "$tmp/empty"
"$relume" relight "$room" --sky "$tmp/empty" -o "$tmp/emptyframes" 2>"$tmp/empty.err"
check "a folder with no sky image is an error saying so" "[ $? -eq 1 ] && grep -q 'no HDR sky image' '$tmp/empty.err'"

exit $fail
