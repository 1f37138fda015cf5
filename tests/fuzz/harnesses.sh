# The fuzzing harnesses' names for the shell scripts, read from tests/fuzz/harnesses.cmake (the one list).
mapfile -t relume_fuzz_harnesses < <(sed -n '/set(relume_fuzz_harnesses/,/)/p' "$(dirname "${BASH_SOURCE[0]}")/harnesses.cmake" |
  sed -e 's/set(relume_fuzz_harnesses//' -e 's/)//' | tr -s ' \n' '\n' | sed '/^$/d')
