"""Soak: train the cartpole with rsl_rl for a long time, interrupted by Ctrl+C and resumed, and watch memory.

    python scripts/benchmarks/soak.py --device cpu --duration 1800 --cycles 6
    python scripts/benchmarks/soak.py --device cuda --duration 1800 --cycles 6

The time is split into ``--cycles`` trainings of ``simlab train`` in a child process. Each is sent
SIGINT (what Ctrl+C sends) at the end of its share; it saves a checkpoint and exits, and the next one
resumes with ``--checkpoint <previous run>``. Every ``--sample_interval`` seconds the child's resident
memory (host RSS, from /proc) and, on cuda, the GPU's used memory (nvidia-smi) are sampled.

Reported: memory over time, per cycle the checkpoints written, the iteration it resumed at and the one
it stopped at (a resume continues when it starts at the iteration of the checkpoint it was given), and
the final policy's criterion of ``cartpole_learns.py`` (|pole angle| < 0.2 rad in >= 95% of the steps
of 64 envs for 5 s).
"""

from __future__ import annotations

import argparse
import dataclasses
import glob
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field

from cartpole_learns import pole_angle_tracker

from simlab.cli.main import EXIT_INTERRUPTED, build_parser
from simlab.cli.play import run_play

_RESUMED = re.compile(r"\[simlab\] Resumed from (\S+) at iteration (\d+)")
_SAVED = re.compile(r"\[simlab\] Interrupted: saved (\S+)")
_CHECKPOINT = re.compile(r"model_(\d+)\.pt$")


@dataclass
class Cycle:
    index: int
    run_dir: str = ""
    exit_code: int | None = None
    resumed_from: str | None = None
    resumed_at: int | None = None
    expected_start: int | None = None
    stopped_at: int | None = None
    checkpoints: list[str] = field(default_factory=list)
    samples: list[tuple[float, float, float | None]] = field(default_factory=list)
    """(seconds since the soak started, host RSS MiB, GPU used MiB or None)."""

    @property
    def continued(self) -> bool | None:
        """Whether the resume started at the given checkpoint's iteration (None for the first cycle)."""
        if self.expected_start is None:
            return None
        return self.resumed_at == self.expected_start


def rss_mib(pid: int) -> float | None:
    """Resident memory of ``pid`` [MiB], from /proc (None once the process is gone)."""
    try:
        with open(f"/proc/{pid}/status") as status:
            for line in status:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1]) / 1024.0
    except OSError:
        return None
    return None


def gpu_used_mib(device: str) -> float | None:
    """Memory in use on the GPU of ``device`` [MiB] (the whole GPU: run the soak alone on it)."""
    if not device.startswith("cuda") or shutil.which("nvidia-smi") is None:
        return None
    index = device.split(":")[1] if ":" in device else "0"
    out = subprocess.run(
        ["nvidia-smi", f"--id={index}", "--query-gpu=memory.used", "--format=csv,noheader,nounits"],
        capture_output=True,
        text=True,
    )
    try:
        return float(out.stdout.strip().splitlines()[0])
    except (IndexError, ValueError):
        return None


def iteration_of(checkpoint: str) -> int | None:
    match = _CHECKPOINT.search(os.path.basename(checkpoint))
    return int(match.group(1)) if match else None


def _hear_sigint() -> None:
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def run_cycle(cycle: Cycle, args: argparse.Namespace, previous: Cycle | None, start: float) -> None:
    """One ``simlab train`` child: run it for ``args.duration / args.cycles`` seconds, then SIGINT."""
    run_name = f"soak{cycle.index}"
    cmd = [sys.executable, "-m", "simlab", "train", "--task", args.task, "--library", "rsl_rl", "--headless"]
    cmd += ["--log_root", args.log_root, "--run_name", run_name, "--max_iterations", "1000000"]
    cmd += ["--device", args.device, "--seed", str(args.seed)]
    if args.num_envs is not None:
        cmd += ["--num_envs", str(args.num_envs)]
    if previous is not None:
        cmd += ["--checkpoint", previous.run_dir]
        cycle.expected_start = previous.stopped_at
    log_path = os.path.join(args.log_root, f"{run_name}.log")
    print(f"\n=== cycle {cycle.index}: {' '.join(cmd[1:])}", flush=True)
    share = args.duration / args.cycles
    with open(log_path, "w") as log:
        child = subprocess.Popen(
            cmd,
            stdout=log,
            stderr=subprocess.STDOUT,
            env={**os.environ, "PYTHONUNBUFFERED": "1"},
            # a soak started in the background (`cmd &`) inherits an ignored SIGINT; the child must hear it
            preexec_fn=_hear_sigint,
        )
        began = time.time()
        next_sample = began + args.sample_interval  # not at 0 s: the child has not imported anything yet
        while child.poll() is None and time.time() - began < share:
            if time.time() >= next_sample:
                rss = rss_mib(child.pid)
                if rss is not None:
                    sample = (time.time() - start, rss, gpu_used_mib(args.device))
                    cycle.samples.append(sample)
                    gpu = f", GPU {sample[2]:.0f} MiB" if sample[2] is not None else ""
                    print(f"  t={sample[0]:7.1f} s  RSS {rss:7.1f} MiB{gpu}", flush=True)
                next_sample += args.sample_interval
            time.sleep(0.2)
        if child.poll() is None:
            child.send_signal(signal.SIGINT)
        try:
            cycle.exit_code = child.wait(timeout=180)
        except subprocess.TimeoutExpired:
            child.kill()
            cycle.exit_code = child.wait()
    with open(log_path, errors="replace") as log:
        text = log.read()
    if resumed := _RESUMED.search(text):
        cycle.resumed_from, cycle.resumed_at = resumed.group(1), int(resumed.group(2))
    if saved := _SAVED.search(text):
        cycle.stopped_at = iteration_of(saved.group(1))
        cycle.run_dir = os.path.dirname(saved.group(1))
    else:
        runs = glob.glob(os.path.join(args.log_root, "rsl_rl", "*", f"*_{run_name}"))
        cycle.run_dir = runs[0] if runs else ""
        print(f"  cycle {cycle.index} saved no checkpoint on SIGINT (exit {cycle.exit_code}); see {log_path}")
    cycle.checkpoints = sorted(
        glob.glob(os.path.join(cycle.run_dir, "model_*.pt")) if cycle.run_dir else [], key=lambda p: iteration_of(p)
    )


def earlier_cycle(run_dir: str) -> Cycle:
    """The last cycle of an earlier soak, rebuilt from its run folder, for the first cycle to resume from."""
    checkpoints = sorted(glob.glob(os.path.join(run_dir, "model_*.pt")), key=iteration_of)
    if not checkpoints:
        raise SystemExit(f"--resume_from {run_dir}: no model_*.pt checkpoint there to resume from")
    print(f"resuming the soak from {checkpoints[-1]}")
    newest = iteration_of(checkpoints[-1])
    return Cycle(-1, run_dir=os.path.abspath(run_dir), stopped_at=newest, checkpoints=checkpoints)


def evaluate(run_dir: str, args: argparse.Namespace) -> float:
    """Fraction of env-steps with |pole angle| < threshold, playing the run's newest checkpoint."""
    argv = ["play", "--task", args.task, "--library", "rsl_rl", "--checkpoint", run_dir, "--headless"]
    argv += ["--num_envs", str(args.eval_envs), "--device", args.device, "--log_root", args.log_root, "--no_export"]
    play_args = build_parser().parse_args([*argv, "--seconds", str(args.eval_seconds)])
    on_step, counts = pole_angle_tracker(args.threshold)
    run_play(play_args, [], on_step=on_step)
    return counts["inside"] / max(1, counts["total"])


def report(cycles: list[Cycle], args: argparse.Namespace, criterion: float | None) -> bool:
    print(f"\n=== soak: {args.task}, rsl_rl, {args.device}, {args.duration:.0f} s in {args.cycles} cycles")
    print(
        f"{'cycle':>5} {'exit':>5} {'resumed at':>10} {'expected':>8} {'continued':>9} {'stopped at':>10}"
        f" {'ckpts':>5} {'RSS first':>9} {'RSS last':>8} {'RSS max':>8}  GPU last [MiB]"
    )
    for c in cycles:
        rss = [s[1] for s in c.samples]
        gpu = [s[2] for s in c.samples if s[2] is not None]
        print(
            f"{c.index:>5} {c.exit_code!s:>5} {c.resumed_at!s:>10} {c.expected_start!s:>8} {c.continued!s:>9}"
            f" {c.stopped_at!s:>10} {len(c.checkpoints):>5} {rss[0] if rss else float('nan'):>9.1f}"
            f" {rss[-1] if rss else float('nan'):>8.1f} {max(rss) if rss else float('nan'):>8.1f}"
            f"  {f'{gpu[-1]:.0f}' if gpu else '-'}"
        )
    total = sum(len(c.checkpoints) for c in cycles)
    resumes = [c for c in cycles if c.expected_start is not None]
    continued = all(c.continued for c in resumes)
    saved = all(c.exit_code == EXIT_INTERRUPTED and c.stopped_at is not None for c in cycles)
    print(f"checkpoints written: {total}; resumes: {len(resumes)}, all continued the iteration counter: {continued}")
    print(f"every cycle saved on SIGINT and exited {EXIT_INTERRUPTED}: {saved}")
    # Flat memory: the RSS at the end of each cycle (same phase: a trained-for-a-while process) should not grow.
    ends = [c.samples[-1][1] for c in cycles if c.samples]
    flat = True
    if len(ends) >= 2:
        growth = (ends[-1] - min(ends)) / min(ends)
        flat = growth <= args.rss_tolerance
        print(
            f"RSS at the end of each cycle [MiB]: {', '.join(f'{e:.1f}' for e in ends)}"
            f" (growth {growth:+.1%}, tolerance {args.rss_tolerance:.0%}: {'flat' if flat else 'GROWING'})"
        )
    passed = continued and saved and flat
    if criterion is not None:
        learned = criterion >= args.fraction
        print(
            f"final policy: |pole angle| < {args.threshold} rad in {criterion:.1%} of steps"
            f" (needs {args.fraction:.0%}): {'yes' if learned else 'no'}"
        )
        passed = passed and learned
    print(f"soak {'PASSED' if passed else 'FAILED'}")
    return passed


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--device", default="cpu", help="cpu, cuda or cuda:N.")
    parser.add_argument("--duration", type=float, default=1800.0, help="Seconds of training in all (default 30 min).")
    parser.add_argument("--cycles", type=int, default=6, help="Trainings, each stopped by SIGINT, resumed by the next.")
    parser.add_argument("--task", default="simlab/Cartpole-v0")
    parser.add_argument("--num_envs", type=int, default=None, help="Training envs (default: the task's).")
    parser.add_argument("--seed", type=int, default=42)
    parser.add_argument("--sample_interval", type=float, default=10.0, help="Seconds between memory samples.")
    parser.add_argument("--log_root", default=None, help="Where the runs go (default: a new temporary folder).")
    parser.add_argument("--rss_tolerance", type=float, default=0.05, help="Allowed RSS growth between cycle ends.")
    parser.add_argument("--eval_envs", type=int, default=64)
    parser.add_argument("--eval_seconds", type=float, default=5.0)
    parser.add_argument("--threshold", type=float, default=0.2, help="Pole angle bound [rad].")
    parser.add_argument("--fraction", type=float, default=0.95, help="Required fraction of steps inside.")
    parser.add_argument("--json", default=None, help="Also write the cycles, memory samples and criterion here.")
    parser.add_argument(
        "--resume_from",
        default=None,
        help="Run folder of an earlier soak (its last cycle): the first cycle resumes from its newest checkpoint,"
        " so one soak can go on in another process or on another machine.",
    )
    args = parser.parse_args()
    if args.cycles < 1 or args.duration <= 0:
        parser.error("--cycles must be at least 1 and --duration positive")
    args.log_root = os.path.abspath(args.log_root or tempfile.mkdtemp(prefix="simlab_soak_"))
    os.makedirs(args.log_root, exist_ok=True)
    print(f"runs and child logs in {args.log_root}")

    start = time.time()
    cycles: list[Cycle] = []
    earlier = earlier_cycle(args.resume_from) if args.resume_from else None
    for index in range(args.cycles):
        cycle = Cycle(index)
        run_cycle(cycle, args, cycles[-1] if cycles else earlier, start)
        cycles.append(cycle)
        if cycle.stopped_at is None:
            break  # nothing to resume from
    last = cycles[-1]
    criterion = evaluate(last.run_dir, args) if last.checkpoints else None
    passed = report(cycles, args, criterion)
    if args.json:
        result = {"args": vars(args), "cycles": [dataclasses.asdict(c) for c in cycles], "criterion": criterion}
        with open(args.json, "w") as out:
            json.dump({**result, "passed": passed}, out, indent=1)
    return 0 if passed else 1


if __name__ == "__main__":
    sys.exit(main())
