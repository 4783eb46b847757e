#!/usr/bin/env bash
# The GPU benchmark runs behind docs/performance.md. Run on a GPU machine from the repo root;
# results go to $OUT (default bench_out/) as JSON plus the printed tables.
#   bash scripts/benchmarks/gpu_suite.sh physics|env|train
set -u
OUT=${OUT:-bench_out}
mkdir -p "$OUT"
bench() { python3 -m simlab.benchmarks.cli "$@" 2>"$OUT/stderr_$1.log" | grep -v -E '^\||^\+|^\[INFO|^\t|Module .* load|^Seed not set' ; }
case "${1:-all}" in
  physics|all)
    bench physics --device cuda:0 --robots cartpole ant humanoid --num_envs 4096 65536 --json "$OUT/physics.json" ;;&
  env|all)
    bench env --device cuda:0 --tasks simlab/Cartpole-v0 simlab/Cartpole-Direct-v0 --num_envs 4096 65536 131072 \
      --cuda_graph both --json "$OUT/env_cartpole.json"
    bench env --device cuda:0 --tasks simlab/Ant-Direct-v0 simlab/Humanoid-Direct-v0 --num_envs 4096 \
      --cuda_graph both --json "$OUT/env_locomotion.json" ;;&
  train|all)
    bench train --device cuda:0 --tasks simlab/Cartpole-v0 simlab/Humanoid-Direct-v0 --num_envs 4096 \
      --iterations 10 --json "$OUT/train.json" ;;
esac
