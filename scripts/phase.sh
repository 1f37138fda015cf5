# Sourced by the test scripts: `phase NAME COMMAND...` runs a command and records its wall time,
# printed when the script ends (and appended to $RELUME_PHASE_LOG where .ci/run set it).
relume_phases=()
phase() {
  local name=$1 t=$SECONDS rc=0
  shift
  "$@" || rc=$?
  relume_phases+=("$(printf '  %-26s %6d s%s' "$name" $((SECONDS - t)) "$([ $rc -eq 0 ] || echo " (failed, exit $rc)")")")
  return $rc
}
relume_phase_report() {
  [ ${#relume_phases[@]} -gt 0 ] || return 0
  echo "--- wall time per phase:"
  printf '%s\n' "${relume_phases[@]}"
  [ -n "${RELUME_PHASE_LOG:-}" ] && printf '%s\n' "${relume_phases[@]}" >> "$RELUME_PHASE_LOG"
  return 0
}
trap relume_phase_report EXIT
