#!/bin/bash
# A generated barn (scripts/sitegen) run in closed loop by fleetnav-scenario and judged by the
# simulator's ground truth: the feeding round succeeds, docked, with 0 contacts.
#   generated_barn_test.sh BUILD_DIR SEED [--error-cases]
set -euo pipefail
build="$1"
seed="$2"
shift 2
here="$(cd "$(dirname "$0")" && pwd)"
work="$(mktemp -d /tmp/generated-barn.XXXXXX)"
trap 'rm -rf "$work"' EXIT
"$here/../../scripts/sitegen" barn --seed "$seed" --out "$work/site" "$@"
"$build/tools/fleetnav-scenario" run "$work/site/scenario.yaml" --keep "$work/run"
