#!/usr/bin/env bash
# Every binary fleetnav ships answers --version and --help with exit code 0 (issue 38): the
# version line carries the project's version, the help names the binary's options.
# Usage: version_and_help_test.sh VERSION BINARY...
set -u
version="$1"
shift
failures=0
for binary in "$@"; do
  name=$(basename "$binary")
  out=$("$binary" --version 2>&1)
  code=$?
  if [ "$code" -ne 0 ]; then
    echo "FAIL: $name --version exited $code: $out"
    failures=$((failures + 1))
  elif [[ "$out" != *"$version"* ]]; then
    echo "FAIL: $name --version printed '$out', not the version $version"
    failures=$((failures + 1))
  fi
  out=$("$binary" --help 2>&1)
  code=$?
  if [ "$code" -ne 0 ]; then
    echo "FAIL: $name --help exited $code"
    failures=$((failures + 1))
  elif [[ "$out" != *"--"* ]]; then
    echo "FAIL: $name --help printed no option: $out"
    failures=$((failures + 1))
  fi
done
passed=$(($# * 2 - failures))
echo "$passed passed, $failures failed"
[ "$failures" -eq 0 ]
