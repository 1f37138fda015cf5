# The fuzzing harnesses, one per parser (tests/fuzz/NAME.cpp): built as libFuzzer targets by
# tests/fuzz/CMakeLists.txt (scripts/fuzz.sh) and as replay drivers by the sanitized build
# (tests/CMakeLists.txt, scripts/test-sanitized.sh).
set(relume_fuzz_harnesses colmap_text colmap_binary project obj bundle obj_json variant relight intrinsics workspace
    clicks sky_description fisheye_lens ies ldt fan mesh)
