#!/usr/bin/env bash
# The slow test set: learning checks (training or playing to a threshold: every shipped policy meets
# its criterion) and other long end-to-end runs, which the default `pytest -q` leaves out. Run it
# nightly and before a release; on the 2-core CPU machine it takes longer than the default set.
#   bash scripts/nightly.sh                 # the slow set
#   bash scripts/nightly.sh -k pretrained   # a part of it (pytest's flags pass through)
set -euo pipefail
cd "$(dirname "$0")/.."
[ -x .venv/bin/python ] || bash scripts/setup.sh dev
.venv/bin/python -m pytest -q -m slow --durations=25 "$@"
