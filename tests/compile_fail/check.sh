#!/usr/bin/env bash
# Compiles a file that must not compile and checks that the compiler says
# what the library says, in exactly one error, with no follow-on errors:
#   check.sh MESSAGE_REGEX COMPILER ARGS...
set -uo pipefail
message=$1
shift
out=$("$@" 2>&1)
status=$?
errors=$(grep -c "error:" <<< "$out")
if [ "$status" -eq 0 ]; then
  echo "compile-fail: the file compiled"
  exit 1
fi
if ! grep -Eq "$message" <<< "$out"; then
  printf 'compile-fail: the message /%s/ is missing; the compiler said:\n%s\n' "$message" "$out"
  exit 1
fi
if [ "$errors" -ne 1 ]; then
  printf 'compile-fail: %s errors instead of one:\n%s\n' "$errors" "$out"
  exit 1
fi
echo "compile-fail: one error, the library's sentence"
