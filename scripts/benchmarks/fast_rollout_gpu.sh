#!/usr/bin/env bash
# issue 19, the rollout step: what agent.fast_rollout changes on the GPU, in one run from the repo root.
#   bash scripts/benchmarks/fast_rollout_gpu.sh [device [envs...]]       (default: cuda:0 4096 16384)
# SOLVE_ARGS adds flags to the solve line (a CPU trial: SOLVE_ARGS="--num_envs 64 --max_iterations 1").
# 1. the CUDA equivalence tests (graphed rollout step = rsl_rl's, graphed act and update);
# 2. a rollout step's ops and time by source at the first env count, rsl_rl's step then simlab's;
# 3. `bench train` with both rollout steps at each env count (JSON in $OUT);
# 4. `bench solve` of cartpole with simlab's rollout step (learning unchanged: it still solves).
set -u
OUT=${OUT:-bench_out}
DEVICE=${1:-cuda:0}
shift || true
ENVS=${*:-4096 16384}
mkdir -p "$OUT"
quiet() { grep -v -E $'^\\||^\\+|^\\[INFO|^\t|^  [a-z_]+: [a-z]+ at /World|^Active Recorder|Module .* load|^Seed not set|it/s\\]|^Storing git' ; }
python3 -m pytest -q -p no:cacheprovider tests/test_rsl_rl_fast_rollout.py tests/test_rsl_rl_fast_update.py 2>&1 | tail -3
for step in rsl_rl fast; do
  python3 scripts/benchmarks/rollout_step_ops.py --device "$DEVICE" --num_envs "${ENVS%% *}" --rollout "$step" 2>&1 | quiet
done
python3 -m simlab.benchmarks.cli train --device "$DEVICE" --tasks simlab/Cartpole-v0 --num_envs $ENVS \
  --iterations 20 --rollout_step both --json "$OUT/train_rollout_step.json" 2>"$OUT/stderr_train.log" | quiet
python3 -m simlab.benchmarks.cli solve --device "$DEVICE" --tasks simlab/Cartpole-v0 --eval_every 5 --seed 1 \
  --rollout_step fast --log_root "$OUT/logs" --json "$OUT/solve_rollout_step.json" ${SOLVE_ARGS:-} 2>"$OUT/stderr_solve.log" | quiet
