#!/usr/bin/env bash
# The unit tests built with AddressSanitizer + UndefinedBehaviorSanitizer (-fno-sanitize-recover:
# the first report fails the run), into build-asan/. CI runs it after scripts/test.sh.
#
# Every unit test binary runs whole, except relight_tests, which runs its quick tests: its others
# each preprocess the sample room, 15-60 s apiece under the sanitizers, and run in the normal
# build only (scripts/test.sh); so do daylight_tests' slowest tests (listed below). The GUI and
# end-to-end tests run in the normal build only. Then
# the fuzzing corpora and regression inputs replay through the harnesses (tests/fuzz), built in
# the same tree from the same sanitized modules. Each phase's wall time is printed at the end.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/phase.sh
targets=(geometry_tests raytrace_tests project_tests radiosity_tests reconstruct_tests relight_tests
         daylight_tests ibr_tests)
source tests/fuzz/harnesses.sh
for h in "${relume_fuzz_harnesses[@]}"; do targets+=("fuzz_$h"); done
sanitized_build() {
  cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRELUME_SANITIZE=ON ${RELUME_CMAKE_ARGS:-} &&
    cmake --build build-asan -j "$(nproc)" --target "${targets[@]}"
}
phase "sanitized build" sanitized_build
export ASAN_OPTIONS="detect_leaks=1:halt_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1"
export LSAN_OPTIONS="suppressions=$PWD/tests/sanitizer/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
quick_relight="Relight.BadInputIsRefusedWithAClearError:Relight.TheShadowTestFailsOnAnImageThatKeepsTheOldShadow:"
quick_relight+="Relight.EstimatesLampsNearTheirTrueEmittance:Relight.ProjectRoundTripRelightsTheSame:"
quick_relight+="Relight.VirtualLampBrightensWhatItFaces:Textures.TexelsPhotographedAtAPolygonsOutline*"
mkdir -p build-asan/logs
run() {  # name, gtest filter
  local log="build-asan/logs/$1.log" start=$SECONDS
  if "build-asan/tests/$1" --gtest_filter="$2" > "$log" 2>&1; then
    echo "sanitized $1: passed ($((SECONDS - start)) s)"
  else
    echo "sanitized $1: FAILED ($((SECONDS - start)) s), see $log:"
    grep -E -A12 "ERROR: (Address|Leak)Sanitizer|runtime error|\[  FAILED  \]" "$log" | head -60
    return 1
  fi
}
# Two at a time from one queue, longest first (the machine has two cores; each binary's TBB work is
# mostly serial here). daylight_tests runs without the tests that solve a room's bases three times
# over, on the exact sky, or on the daylight sample room (13 min for the interactive path alone
# under the sanitizers): the same code runs here on the smaller rooms of the other daylight tests;
# those run in the normal build only.
slow_daylight="DaylightRelight.TheInteractivePath*:DaylightSampleRoom.T*:DaylightSampleRoom.A*:"
slow_daylight+="DaylightSampleRoom.R*:DaylightBasis.AVirtualLampShinesAsTheSameLampSolvedAlone*:"
slow_daylight+="DaylightBasis.RegionsCombinedMatchTheExactSky*:DaylightRelight.AOneSidedVirtualLamp*"
queue=("daylight_tests -$slow_daylight" "ibr_tests *" "relight_tests $quick_relight"
       "radiosity_tests *" "reconstruct_tests *" "project_tests *" "geometry_tests *"
       "raytrace_tests *")
sanitized_run() {
  local status=0 running=0
  for job in "${queue[@]}"; do
    if [ "$running" -ge 2 ]; then wait -n || status=1; running=$((running - 1)); fi
    run ${job%% *} "${job#* }" & running=$((running + 1))
  done
  while [ "$running" -gt 0 ]; do wait -n || status=1; running=$((running - 1)); done
  return $status
}
# The fuzzing corpora and every crash input found (tests/fuzz/regressions), replayed through the
# parsers' harnesses under the same sanitizers (g++; libFuzzer's engine is not needed to replay).
fuzz_replay() {
  local status=0 h name out inputs
  for h in tests/fuzz/*.cpp; do  # a harness left out of the list would never be replayed
    name=$(basename "$h" .cpp)
    [ "$name" = replay_main ] || [[ " ${relume_fuzz_harnesses[*]} " == *" $name "* ]] ||
      { echo "sanitized fuzz replay: $h is not in tests/fuzz/harnesses.cmake"; status=1; }
  done
  for name in "${relume_fuzz_harnesses[@]}"; do
    inputs=(tests/fuzz/corpus/"$name")
    [ -d tests/fuzz/regressions/"$name" ] && inputs+=(tests/fuzz/regressions/"$name")
    if out=$(build-asan/tests/fuzz_"$name" "${inputs[@]}" 2>&1); then
      echo "sanitized fuzz replay $name: $out"
    else
      echo "sanitized fuzz replay $name: FAILED"
      echo "$out" | tail -40
      status=1
    fi
  done
  return $status
}
status=0
phase "sanitized unit tests" sanitized_run || status=1
phase "sanitized fuzz replays" fuzz_replay || status=1
exit $status
