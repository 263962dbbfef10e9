#!/bin/bash
# A generated store or yard (scripts/sitegen) run in closed loop by fleetnav-scenario and judged
# by the simulator's ground truth: the route's job succeeds with 0 contacts before its deadline.
#   generated_site_test.sh BUILD_DIR KIND SEED      (KIND: store or yard)
set -euo pipefail
if [ $# -ne 3 ] || { [ "$2" != store ] && [ "$2" != yard ]; }; then
  echo "usage: $0 BUILD_DIR store|yard SEED" >&2
  exit 2
fi
build="$1"
kind="$2"
seed="$3"
here="$(cd "$(dirname "$0")" && pwd)"
work="$(mktemp -d "/tmp/generated-$kind.XXXXXX")"
trap 'rm -rf "$work"' EXIT
"$here/../../scripts/sitegen" "$kind" --seed "$seed" --out "$work/site"
"$build/tools/fleetnav-scenario" run "$work/site/scenario.yaml" --keep "$work/run"
