#!/usr/bin/env bash
# Crashes real `relume` commands while they save over an existing project, and checks that the
# user's path still holds the previous project or the new one, never neither.
#
#   scripts/crash-saves.sh [--relume BINARY] [--steps] [--quick] [--fallback] [--kill9 TRIALS] COMMAND...
#
# COMMAND: import, triangulate, preprocess, or import-preprocessed (`relume import` of a preprocessed
# project: the save the workbench's Save makes), each saving over an existing project built from
# the bundled sample room.
#   --steps      crash at every file-system step of the save in turn (RELUME_CRASH_AT_SAVE_STEP=N,
#                which sends the process SIGKILL at its N-th step), until the command finishes.
#   --snapshots  one uninterrupted run that copies, at every file-system step, what a crash there
#                would leave (RELUME_SAVE_SNAPSHOTS=DIR); each copy is then checked as after a
#                crash. The same states as --steps from one run of the command (for preprocess,
#                whose every run takes seconds before its save).
#   --fallback   saves without the atomic directory exchange (RELUME_SAVE_NO_EXCHANGE), as on a
#                file system that lacks it: two renames, the old project kept aside between them.
#   --quick      after each crash, compare the whole folder at the path with the old and the new
#                project byte for byte (instead of relighting it: what CI runs).
#   --kill9 N    real `kill -9`s from outside, each at a random moment of the save phase (from
#                its staging folder's appearing to the command's end, timed on one run first),
#                until N of them landed before the command ended.
# After every crash: `relume check` opens the path (exit 0), its project.json is byte for byte the
# old or the new one, a preprocessed project relights to the old or the new one's image
# (>= 50 dB), and saving again over it succeeds. Prints the counts; exits 1 on any failure.
set -u
here=$(cd "$(dirname "$0")/.." && pwd)
relume=$here/build/app/cli/relume
steps=0
snapshots=0
kills=0
quick=0
commands=()
while [ $# -gt 0 ]; do
  case $1 in
    --relume) relume=${2:?--relume needs the binary}; shift 2 ;;
    --steps) steps=1; shift ;;
    --snapshots) snapshots=1; shift ;;
    --kill9) kills=${2:?--kill9 needs a number of trials}; shift 2 ;;
    --quick) quick=1; shift ;;
    --fallback) export RELUME_SAVE_NO_EXCHANGE=1; shift ;;
    -h|--help) sed -n '2,25p' "$0"; exit 0 ;;
    *) commands+=("$1"); shift ;;
  esac
done
[ ${#commands[@]} -gt 0 ] || { echo "give a command: import, triangulate, preprocess or import-preprocessed" >&2; exit 2; }
room=$here/resources/sample_room
[ -x "$relume" ] || { echo "no $relume: build first (scripts/build.sh)" >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failed=0

# The command that writes the NEW project to $1 (the old one is made differently, so the two
# differ), as the array `args`; new_cmd runs it.
new_args() {
  case $cmd in
    import) args=("$relume" import "$room" -o "$1") ;;
    triangulate) args=("$relume" triangulate "$room/colmap" --clicks "$room/clicks.json" -o "$1") ;;
    preprocess) args=("$relume" preprocess "$room" -o "$1") ;;
    import-preprocessed) args=("$relume" import "$tmp/source" -o "$1") ;;
  esac
}
new_cmd() {
  new_args "$1"
  "${args[@]}"
}
old_cmd() {
  case $cmd in
    import | triangulate) "$relume" import "$room" -o "$1" && sed -i 's/"albedo": \[/"albedo": [0.01, 0.02, 0.03], "was": [/' "$1/project.json" ;;
    preprocess | import-preprocessed) "$relume" preprocess "$room" --mean-reflectance 0.4 -o "$1" ;;
  esac
}

# Whether two project folders are the same byte for byte, but for the run-dependent figures of
# their JSON files (lines with "seconds": how long the command took).
same_folder() {
  diff -rq -x '*.json' "$1" "$2" >/dev/null 2>&1 || return 1
  local f rel
  while IFS= read -r f; do
    rel=${f#"$1"/}
    [ -e "$2/$rel" ] || return 1
    diff -q <(grep -v '"seconds"' "$f") <(grep -v '"seconds"' "$2/$rel") >/dev/null || return 1
  done < <(find "$1" -name '*.json')
  [ "$(find "$1" -name '*.json' | wc -l)" = "$(find "$2" -name '*.json' | wc -l)" ]
}
same_as() {
  local state=
  same_folder "$tmp/target" "$tmp/old" && state=old
  same_folder "$tmp/target" "$tmp/new" && state=new
  echo "$state"
}
# Checks the path after a crash; $1 names the trial.
check_after() {
  local what=$1 p=$tmp/target state=
  # --quick: a folder identical to the old or the new project opens as they do (both were
  # checked); anything else must open (an open may first put a project back) and then be one.
  if [ $quick = 1 ]; then state=$(same_as); fi
  if [ -z "$state" ] && ! "$relume" check "$p" >"$tmp/check.out" 2>&1; then
    echo "FAILED ($what): the path does not open:"; sed 's/^/    /' "$tmp/check.out"; failed=1; return
  fi
  if [ $quick = 1 ]; then
    [ -n "$state" ] || state=$(same_as)
    if [ -z "$state" ]; then echo "FAILED ($what): the folder is neither the old nor the new project"; failed=1; return; fi
    seen[$state]=$((${seen[$state]:-0} + 1))
    return
  fi
  cmp -s "$p/project.json" "$tmp/old/project.json" && state=old
  cmp -s "$p/project.json" "$tmp/new/project.json" && state=new
  if [ -z "$state" ]; then echo "FAILED ($what): project.json is neither the old nor the new one"; failed=1; return; fi
  if [ "$cmd" != import ] && [ "$cmd" != triangulate ]; then
    "$relume" relight "$p" -o "$tmp/after.exr" >/dev/null 2>&1 || { echo "FAILED ($what): does not relight"; failed=1; return; }
    local db
    db=$("$relume" compare "$tmp/after.exr" "$tmp/$state.exr" | sed -n 's/^all \([0-9.]*\) dB.*/\1/p')
    if ! awk -v d="$db" 'BEGIN { exit !(d >= 50) }'; then
      echo "FAILED ($what): relights to ${db} dB of the $state project's image"; failed=1; return
    fi
  fi
  seen[$state]=$((${seen[$state]:-0} + 1))
}

# The next save over what a crash left succeeds and leaves nothing beside the project (tried for
# each kind of leftovers: which folders the crash left beside the path; with --quick once per
# kind, otherwise after every step). $1 names the trial.
resave_after() {
  left=$(cd "$tmp" && ls -d .target.* 2>/dev/null | tr '\n' ' ')
  if [ $quick = 0 ] || [ "$left" != "${last_left-none}" ]; then
    resaved=$((resaved + 1))
    if ! new_cmd "$tmp/target" >"$tmp/resave.out" 2>&1 || ls -d "$tmp"/.target.* >/dev/null 2>&1; then
      echo "FAILED ($1): saving again after the crash (leftovers: ${left:-none})"; tail -3 "$tmp/resave.out"; failed=1
    fi
  fi
  last_left=$left
}

reset_target() {
  rm -rf "$tmp/target" "$tmp"/.target.*
  cp -a "$tmp/old" "$tmp/target"
}

for cmd in "${commands[@]}"; do
  case $cmd in import | triangulate | preprocess | import-preprocessed) ;; *) echo "unknown command $cmd" >&2; exit 2 ;; esac
  rm -rf "$tmp/old" "$tmp/new" "$tmp/source"
  if [ "$cmd" = import-preprocessed ]; then
    "$relume" preprocess "$room" -o "$tmp/source" >/dev/null 2>&1 || { echo "cannot preprocess the sample room" >&2; exit 1; }
  fi
  old_cmd "$tmp/old" >/dev/null 2>&1 || { echo "cannot make the old project for $cmd" >&2; exit 1; }
  new_cmd "$tmp/new" >/dev/null 2>&1 || { echo "cannot make the new project for $cmd" >&2; exit 1; }
  "$relume" check "$tmp/old" >/dev/null 2>&1 && "$relume" check "$tmp/new" >/dev/null 2>&1 ||
    { echo "the old or the new project for $cmd does not open" >&2; exit 1; }
  if [ "$cmd" != import ] && [ "$cmd" != triangulate ] && [ $quick = 0 ]; then
    "$relume" relight "$tmp/old" -o "$tmp/old.exr" >/dev/null 2>&1 && "$relume" relight "$tmp/new" -o "$tmp/new.exr" >/dev/null 2>&1 ||
      { echo "cannot relight the reference projects" >&2; exit 1; }
  fi
  if [ $steps = 1 ]; then
    declare -A seen=()
    n=1
    resaved=0
    unset last_left
    while :; do
      reset_target
      RELUME_CRASH_AT_SAVE_STEP=$n new_cmd "$tmp/target" >"$tmp/run.out" 2>&1
      rc=$?
      if [ $rc -eq 0 ]; then break; fi
      if [ $rc -ne 137 ]; then echo "FAILED ($cmd step $n): exit $rc, not killed:"; tail -3 "$tmp/run.out"; failed=1; break; fi
      check_after "$cmd, killed at save step $n"
      resave_after "$cmd step $n"
      n=$((n + 1))
    done
    echo "$cmd: killed at each of $((n - 1)) save steps: old project at the path ${seen[old]:-0} times, new ${seen[new]:-0} times; saved again after $resaved of them"
    unset seen
  fi
  if [ $snapshots = 1 ]; then
    declare -A seen=()
    resaved=0
    unset last_left
    reset_target
    rm -rf "$tmp/snaps"
    RELUME_SAVE_SNAPSHOTS=$tmp/snaps new_cmd "$tmp/target" >"$tmp/run.out" 2>&1 ||
      { echo "FAILED ($cmd): the run that takes the snapshots failed:"; tail -3 "$tmp/run.out"; failed=1; continue; }
    same_as_new=$(same_folder "$tmp/target" "$tmp/new" && echo yes)
    [ "$same_as_new" = yes ] || { echo "FAILED ($cmd): the run that takes the snapshots wrote another project"; failed=1; continue; }
    count=0
    last_print=
    for n in $(ls "$tmp/snaps" | sort -n); do
      count=$((count + 1))
      # A step that left the same files at the path (the same inodes: the snapshots are hard
      # links) and the same folders beside it leaves what the step before left: same verdict.
      print=$(cd "$tmp/snaps/$n" && { find target -printf '%i %P\n' 2>/dev/null | sort; ls -d .target.* 2>/dev/null; })
      if [ $quick = 1 ] && [ -n "$last_print" ] && [ "$print" = "$last_print" ] && [ -n "$last_state" ]; then
        seen[$last_state]=$((${seen[$last_state]:-0} + 1))
        continue
      fi
      rm -rf "$tmp/target" "$tmp"/.target.*
      cp -al "$tmp/snaps/$n/." "$tmp/" 2>/dev/null || cp -a "$tmp/snaps/$n/." "$tmp/"
      before_old=${seen[old]:-0}
      before_failed=$failed
      check_after "$cmd, as a crash at save step $n leaves it"
      last_state=
      if [ $failed = "$before_failed" ]; then
        [ "${seen[old]:-0}" != "$before_old" ] && last_state=old || last_state=new
      fi
      last_print=$print
      resave_after "$cmd snapshot $n"
    done
    rm -rf "$tmp/snaps"
    [ "$count" -gt 0 ] || { echo "FAILED ($cmd): no save step was seen"; failed=1; }
    echo "$cmd: what a crash leaves at each of $count save steps (snapshots of one run): old project at the path ${seen[old]:-0} times, new ${seen[new]:-0} times; saved again after $resaved of them"
    unset seen
  fi
  if [ "$kills" -gt 0 ]; then
    declare -A seen=()
    # Aim: how long the save phase lasts (from its staging folder's appearing to the command's
    # end), measured on one uninterrupted run; each kill comes at a random moment within it.
    reset_target
    new_args "$tmp/target"
    "${args[@]}" >"$tmp/run.out" 2>&1 &
    pid=$!
    while kill -0 $pid 2>/dev/null && [ ! -e "$tmp/.target.saving" ]; do sleep 0.001; done
    t0=$(date +%s%N)
    wait $pid
    save_ms=$(( ($(date +%s%N) - t0) / 1000000 ))
    [ $save_ms -ge 1 ] || save_ms=1
    # Until `kills` of them landed before the command ended (at most 3 x as many trials).
    aimed=0
    trials=0
    for ((k = 1; aimed < kills && k <= 3 * kills; ++k)); do
      trials=$k
      reset_target
      new_args "$tmp/target"
      "${args[@]}" >"$tmp/run.out" 2>&1 &  # relume itself, not a subshell, is what gets killed
      pid=$!
      while kill -0 $pid 2>/dev/null && [ ! -e "$tmp/.target.saving" ]; do sleep 0.001; done
      delay=$(( (RANDOM * 32768 + RANDOM) % save_ms ))
      sleep "$(printf '%d.%03d' $((delay / 1000)) $((delay % 1000)))"
      if kill -9 $pid 2>/dev/null; then aimed=$((aimed + 1)); fi
      wait $pid 2>/dev/null
      check_after "$cmd, kill -9 trial $k"
    done
    echo "$cmd: $trials kill -9 trials at random moments of its ${save_ms} ms save phase, $aimed of them before the command ended; after each the path held the old project ${seen[old]:-0} times, the new ${seen[new]:-0} times"
    unset seen
  fi
done
[ $failed = 0 ] && echo "all crashes left the old or the new project" || echo "FAILURES above"
exit $failed
