#!/bin/bash
# A generated barn (scripts/sitegen) run in closed loop by fleetnav-scenario and judged by the
# simulator's ground truth: the feeding round succeeds, docked, with 0 contacts.
#   generated_barn_test.sh BUILD_DIR SEED [--run-seed N] [--error-cases]
# SEED draws the barn; --run-seed sets the run's seed (the simulator's noise and the agent's
# filter; default: the scenario file's).
set -euo pipefail
build="$1"
seed="$2"
shift 2
run_args=()
if [[ "${1:-}" == "--run-seed" ]]; then
  run_args=(--seed "$2")
  shift 2
fi
here="$(cd "$(dirname "$0")" && pwd)"
work="$(mktemp -d /tmp/generated-barn.XXXXXX)"
trap 'rm -rf "$work"' EXIT
"$here/../../scripts/sitegen" barn --seed "$seed" --out "$work/site" "$@"
"$build/tools/fleetnav-scenario" run "$work/site/scenario.yaml" --keep "$work/run" "${run_args[@]}"
