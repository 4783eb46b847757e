"""Make a pretrained policy shipped in simlab/pretrained/ (played by ``simlab play --use_pretrained_checkpoint``).

    python scripts/make_pretrained.py --task simlab/Cartpole-v0 --library rsl_rl

Trains with the task's default agent config and evaluates the policy with
scripts/benchmarks/cartpole_learns.py (|pole angle| < 0.2 rad in >= 95 % of the steps of 64 envs
over 5 s); only a policy that passes is shipped. The run folder's params/, its last checkpoint and the
exported ONNX / TorchScript policy go to simlab/pretrained/<task name>/<library>/, with record.txt
holding the training command and the evaluation's output. Only the cartpole tasks have an evaluation.
"""

from __future__ import annotations

import argparse
import datetime
import os
import shutil
import subprocess
import sys
import tempfile

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EVALUATED_TASKS = ("simlab/Cartpole-v0", "simlab/Cartpole-Direct-v0")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--task", default="simlab/Cartpole-v0", choices=EVALUATED_TASKS)
    parser.add_argument("--library", default="rsl_rl", choices=("rsl_rl", "skrl", "sb3", "rl_games"))
    parser.add_argument("--device", default="cpu")
    args = parser.parse_args()

    from simlab.cli.runs import CHECKPOINT_LAYOUT, find_last_checkpoint, run_dir_of_checkpoint
    from simlab.pretrained import PRETRAINED_DIR

    with tempfile.TemporaryDirectory() as log_root:
        evaluate = [sys.executable, os.path.join(REPO, "scripts", "benchmarks", "cartpole_learns.py")]
        evaluate += ["--task", args.task, "--libraries", args.library, "--log_root", log_root, "--device", args.device]
        done = subprocess.run(evaluate, capture_output=True, text=True)
        print(done.stdout[-3000:], done.stderr[-3000:] if done.returncode else "", sep="\n")
        if done.returncode != 0:
            print("The policy did not pass its evaluation: nothing shipped.", file=sys.stderr)
            return 1
        (experiment,) = os.listdir(os.path.join(log_root, args.library))
        checkpoint = find_last_checkpoint(log_root, args.library, experiment)
        run_dir = run_dir_of_checkpoint(checkpoint, args.library)
        export = [sys.executable, "-m", "simlab", "play", "--task", args.task, "--library", args.library]
        export += ["--checkpoint", checkpoint, "--steps", "1", "--num_envs", "1", "--device", args.device]
        subprocess.run(export, check=True, capture_output=True)

        target = os.path.join(PRETRAINED_DIR, args.task.split("/")[-1], args.library)
        shutil.rmtree(target, ignore_errors=True)
        shutil.copytree(os.path.join(run_dir, "params"), os.path.join(target, "params"))
        checkpoint_dir = os.path.join(target, *CHECKPOINT_LAYOUT[args.library][0])
        os.makedirs(checkpoint_dir, exist_ok=True)
        shutil.copy2(checkpoint, checkpoint_dir)
        shutil.copytree(os.path.join(os.path.dirname(checkpoint), "exported"), os.path.join(checkpoint_dir, "exported"))
        with open(os.path.join(run_dir, "params", "command.txt")) as f:
            command = f.read().strip()
        evaluation = done.stdout[done.stdout.rfind(f"\n{args.task}:") :].strip()
        with open(os.path.join(target, "record.txt"), "w") as f:
            f.write(f"made by: python scripts/make_pretrained.py --task {args.task} --library {args.library}\n")
            f.write(f"date: {datetime.date.today().isoformat()}\ntrained with: {command}\n")
            f.write(f"checkpoint: {os.path.basename(checkpoint)}\nevaluation:\n{evaluation}\n")
    print(f"Shipped {args.task} ({args.library}) in {target}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
