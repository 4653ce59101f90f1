# Sourced by the CLI check scripts: `expect CODE PATTERN -- command...` runs
# the command and counts a failure in $fails unless it exits with CODE and
# (when PATTERN is not empty) its output matches the extended regex PATTERN.
expect() {
  local code=$1 pattern=$2
  shift 3
  local out
  out=$("$@" 2>&1)
  local rc=$?
  if [ "$rc" -ne "$code" ]; then
    echo "FAIL: '$*' exited $rc, expected $code"; echo "$out" | head -20; fails=$((fails + 1)); return
  fi
  if [ -n "$pattern" ] && ! grep -qE -- "$pattern" <<<"$out"; then
    echo "FAIL: '$*' output lacks /$pattern/"; echo "$out" | head -20; fails=$((fails + 1)); return
  fi
  echo "ok: $* -> $rc"
}
