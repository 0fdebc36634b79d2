#!/bin/bash
# Stands in for bin/TOOL during tests/compat/snapshot.sh: runs the real tool,
# passes its stdout, stderr and exit code on, and logs a digest of its stdout.
real="$AUG_REAL_BIN/$(basename "$0")"
out=$(mktemp)
"$real" "$@" > "$out"; rc=$?
cat "$out"
/usr/bin/python3 "$AUG_ROOT/tests/compat/canon.py" "$out" "$rc" "$(basename "$0")" "$@" >> "$AUG_SNAP_LOG"
rm -f "$out"
exit $rc
