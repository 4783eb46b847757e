"""``--distributed``: one training process per GPU (or per CPU worker) on PyTorch's torch.distributed.

Two ways in, one code path:

* under torchrun: ``python -m torch.distributed.run --nproc_per_node=N -m simlab train ... --distributed``.
  torchrun starts the processes and sets ``RANK`` / ``LOCAL_RANK`` / ``WORLD_SIZE``; each process trains.
* ``simlab train --distributed`` on its own: :func:`launch` runs ``torch.distributed.run`` with one process
  per visible GPU (``--nproc_per_node`` on the CPU) and the same command line, as Isaac Lab's
  ``train_multigpu`` does. ``--nnodes`` and the rendezvous flags pass through to torchrun.

Each process simulates its own ``num_envs`` worlds on ``cuda:<local_rank>`` (or the CPU) and seeds with
``seed + rank``; the RL library averages the gradients with its own distributed code (rsl_rl's
``multi_gpu``, skrl's ``config.torch``, rl_games' ``multi_gpu``). Only rank 0 writes the run folder.
The process group uses NCCL on GPUs and gloo on the CPU (which the libraries themselves do not offer:
simlab starts the group and the libraries join it).
"""

from __future__ import annotations

import argparse
import logging
import os
import signal
import subprocess
import sys
from dataclasses import dataclass
from datetime import timedelta
from typing import Any

__all__ = [
    "LAUNCH_FLAGS",
    "SUPPORTED_LIBRARIES",
    "Ranks",
    "add_launch_args",
    "check_same_settings",
    "launch",
    "launch_command",
    "setup_process",
    "stop_once_on_signal",
    "torchrun_ranks",
]

SUPPORTED_LIBRARIES = ("rsl_rl", "skrl", "rl_games")
# torchrun's own flags that `simlab train --distributed` passes through when it launches torchrun
LAUNCH_FLAGS: dict[str, str] = {
    "nproc_per_node": "Processes per node (default: one per visible GPU; required on the CPU).",
    "nnodes": "Number of nodes, or MIN:MAX for elastic runs (torchrun's --nnodes).",
    "node_rank": "Rank of this node (torchrun's --node_rank).",
    "rdzv_backend": "Rendezvous backend, e.g. c10d (torchrun's --rdzv_backend).",
    "rdzv_endpoint": "Rendezvous host:port (torchrun's --rdzv_endpoint).",
    "rdzv_id": "Rendezvous job id shared by all nodes (torchrun's --rdzv_id).",
    "master_addr": "Address of the rank-0 node (torchrun's --master_addr).",
    "master_port": "Port of the rank-0 node (torchrun's --master_port).",
}
# a collective that waits longer than this (a rank gone without torchrun noticing) fails instead of hanging
COLLECTIVE_TIMEOUT = timedelta(minutes=5)


@dataclass(frozen=True)
class Ranks:
    """Where this process stands in the run: its rank over all nodes, on its node, and the process count."""

    rank: int = 0
    local_rank: int = 0
    world_size: int = 1

    @property
    def is_main(self) -> bool:
        """Rank 0: the process that writes the run folder and prints the progress."""
        return self.rank == 0


def torchrun_ranks() -> Ranks | None:
    """The ranks torchrun gave this process, or None when it was not started by torchrun."""
    if "WORLD_SIZE" not in os.environ or "RANK" not in os.environ:
        return None
    return Ranks(
        rank=int(os.environ["RANK"]),
        local_rank=int(os.environ.get("LOCAL_RANK", "0")),
        world_size=int(os.environ["WORLD_SIZE"]),
    )


def add_launch_args(parser: argparse.ArgumentParser) -> None:
    """torchrun's flags on ``simlab train`` (used when simlab launches torchrun itself)."""
    group = parser.add_argument_group("distributed launch (with --distributed, without torchrun)")
    for name, help_text in LAUNCH_FLAGS.items():
        group.add_argument(f"--{name}", default=None, help=help_text)


def _strip_launch_flags(argv: list[str]) -> list[str]:
    """``argv`` without the torchrun flags (``--flag value`` and ``--flag=value`` forms)."""
    flags = {f"--{name}" for name in LAUNCH_FLAGS}
    out: list[str] = []
    skip = False
    for word in argv:
        if skip:
            skip = False
            continue
        if word in flags:
            skip = True
            continue
        if word.split("=", 1)[0] in flags:
            continue
        out.append(word)
    return out


def _processes_per_node(args: argparse.Namespace, device: str) -> int:
    if args.nproc_per_node is not None:
        try:
            count = int(args.nproc_per_node)
        except ValueError:
            raise ValueError(f"--nproc_per_node must be a whole number, got '{args.nproc_per_node}'.") from None
        if count < 1:
            raise ValueError(f"--nproc_per_node must be at least 1, got {count}.")
        return count
    if device == "cpu":
        raise ValueError("--distributed on the CPU needs --nproc_per_node N (the number of training processes).")
    import torch

    return torch.cuda.device_count()


def launch_command(args: argparse.Namespace, argv: list[str], device: str) -> list[str]:
    """The torchrun command line that runs ``simlab <argv>`` once per process."""
    nproc = _processes_per_node(args, device)
    if nproc < 2 and args.nnodes in (None, "1"):
        raise ValueError(
            f"--distributed needs at least 2 processes; this launch would start {nproc} on one node. "
            "Use a machine with several GPUs, --nproc_per_node N or --nnodes N, or train without --distributed."
        )
    cmd = [sys.executable, "-m", "torch.distributed.run", f"--nproc_per_node={nproc}"]
    for name in LAUNCH_FLAGS:
        value = getattr(args, name, None)
        if name != "nproc_per_node" and value is not None:
            cmd.append(f"--{name}={value}")
    if args.nnodes is None and args.rdzv_endpoint is None and args.master_port is None:
        cmd.append("--standalone")  # one node: torchrun picks a free port itself
    return [*cmd, "-m", "simlab", *_strip_launch_flags(argv)]


def launch(args: argparse.Namespace, argv: list[str], device: str) -> int:
    """Run ``simlab <argv>`` under torchrun; returns torchrun's exit code (non-zero if any rank failed)."""
    cmd = launch_command(args, argv, device)
    env = dict(os.environ)
    env["NCCL_NVLS_ENABLE"] = "0"  # NVLink SHARP multicast stays off: the project's GPU hosts need it off
    print(f"[simlab] Launching: {' '.join(cmd)}", flush=True)
    torchrun = subprocess.Popen(cmd, env=env)
    interrupted = False
    while True:
        try:
            code = torchrun.wait()
            break
        except KeyboardInterrupt:
            # the terminal's Ctrl+C reached torchrun and the workers too: rank 0 saves; wait for them
            interrupted = True
    return 130 if interrupted else code


def stop_once_on_signal() -> None:
    """Ctrl+C and torchrun's SIGTERM raise ``KeyboardInterrupt`` once; later ones wait for the save.

    On Ctrl+C the terminal interrupts every worker and torchrun then sends them SIGTERM: the first
    signal stops training (rank 0 saves its checkpoint), the second must not cut the save short.
    """
    stopping = {"raised": False}

    def on_signal(signum: int, frame: Any) -> None:
        if not stopping["raised"]:
            stopping["raised"] = True
            raise KeyboardInterrupt

    signal.signal(signal.SIGINT, on_signal)
    signal.signal(signal.SIGTERM, on_signal)


def setup_process(device: str, ranks: Ranks, start_group: bool = True) -> str:
    """Prepare this torchrun process; returns its device (``cuda:<local_rank>`` for a GPU run, else the CPU).

    Makes that GPU the current one, makes Ctrl+C / torchrun's SIGTERM stop training once, and
    (``start_group``) starts the default process group: NCCL for GPUs, gloo for the CPU. rl_games
    starts its group itself and passes ``start_group=False``.
    """
    import torch
    import torch.distributed as dist

    if device.startswith("cuda"):
        if ranks.local_rank >= torch.cuda.device_count():
            raise ValueError(
                f"Local rank {ranks.local_rank} has no GPU: {torch.cuda.device_count()} visible on this node. "
                "Start at most one process per GPU (--nproc_per_node)."
            )
        device = f"cuda:{ranks.local_rank}"
        torch.cuda.set_device(device)  # NCCL collectives (and rl_games) use the current device
        # NVLink SHARP multicast off unless the user's environment says otherwise (NCCL reads it at start)
        os.environ.setdefault("NCCL_NVLS_ENABLE", "0")
    stop_once_on_signal()
    if start_group and not dist.is_initialized():
        backend = "nccl" if device.startswith("cuda") else "gloo"
        dist.init_process_group(backend, rank=ranks.rank, world_size=ranks.world_size, timeout=COLLECTIVE_TIMEOUT)
    return device


def shutdown() -> None:
    """End this process's part in the process group (every rank, once training is over), so no
    collective thread outlives the interpreter."""
    import torch.distributed as dist

    if dist.is_available() and dist.is_initialized():
        dist.destroy_process_group()


def end_torchrun_worker(code: int) -> None:
    """In a torchrun worker, end the process now with ``code``, skipping the interpreter's teardown;
    elsewhere return. Call it where the command is done and the process would exit next.

    On 2 CPU cores a gloo worker that had finished training, saved and left its process group
    sometimes aborted in that teardown ("terminate called without an active exception", SIGABRT),
    which torchrun reports as a failed run. Everything is written by then (checkpoints saved,
    writers closed); the logging handlers and the standard streams are flushed here.
    """
    if "TORCHELASTIC_RUN_ID" not in os.environ:  # torchrun sets it in its workers
        return
    logging.shutdown()
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)


def check_same_settings(settings: dict[str, Any]) -> None:
    """Fail on every rank, naming the ranks and settings, when the ranks were not started alike.

    Different settings (``num_envs``, the task, the network) would make the ranks' collectives
    disagree in size or number, which deadlocks instead of failing.
    """
    import torch.distributed as dist

    gathered: list[dict[str, Any] | None] = [None] * dist.get_world_size()
    dist.all_gather_object(gathered, settings)
    reference = gathered[0] or {}
    differences = []
    for rank, other in enumerate(gathered[1:], start=1):
        other = other or {}
        for key in sorted(set(reference) | set(other)):
            if reference.get(key) != other.get(key):
                differences.append(f"{key}: rank 0 has {reference.get(key)!r}, rank {rank} has {other.get(key)!r}")
    if differences:
        raise ValueError("The ranks of this distributed run differ: " + "; ".join(differences))
