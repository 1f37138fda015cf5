# Sourced by the test scripts: `phase NAME COMMAND...` runs a command and records its wall time,
# printed when the script ends (and appended to $RELUME_PHASE_LOG where .ci/run set it).
relume_phases=()
phase() {  # (its locals are named apart: bash's functions see their callers' locals)
  local phase_name_=$1 phase_start_=$SECONDS phase_rc_=0
  shift
  "$@" || phase_rc_=$?
  relume_phases+=("$(printf '  %-26s %6d s%s' "$phase_name_" $((SECONDS - phase_start_)) \
                    "$([ $phase_rc_ -eq 0 ] || echo " (failed, exit $phase_rc_)")")")
  return $phase_rc_
}
relume_phase_report() {
  [ ${#relume_phases[@]} -gt 0 ] || return 0
  echo "--- wall time per phase:"
  printf '%s\n' "${relume_phases[@]}"
  [ -n "${RELUME_PHASE_LOG:-}" ] && printf '%s\n' "${relume_phases[@]}" >> "$RELUME_PHASE_LOG"
  return 0
}
trap relume_phase_report EXIT
