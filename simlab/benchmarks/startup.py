"""Where `simlab train` spends its start-up: fresh processes, median milestones, top import costs.

    simlab bench startup --device cpu --runs 5
    simlab bench startup --device cuda:0 --runs 5 --before .device/old

Each run is a new process of ``simlab train --task <task> --headless --max_iterations 1 --verbose``
(the task's env count unless ``--num_envs``), timed from the process start. Variants alternate
run by run, so machine noise falls on all of them alike; compare the ratios:

- ``now``: this tree as it is;
- ``before`` (with ``--before DIR``): the ``simlab`` package in DIR, e.g. an older checkout;
- ``pycache prefix`` (with ``--pycache_prefix DIR``): this tree with ``PYTHONPYCACHEPREFIX=DIR`` and
  without ``PYTHONDONTWRITEBYTECODE``, i.e. every module's bytecode cached in DIR: what start-up is
  where the install has no ``.pyc`` files (``pip install --no-compile``) or Python may not write
  them. Its first run fills DIR; compare the later ones.
- ``no bytecode`` (with ``--no_bytecode_variant``): this tree with an empty ``PYTHONPYCACHEPREFIX`` and
  ``PYTHONDONTWRITEBYTECODE=1``: every module compiled from source in every run, what a host whose
  install has no ``.pyc`` files and whose Python may not write them pays.

Per variant it prints the median (and each run's) seconds from the process start to each of
``simlab train``'s start-up milestones: the configs loaded (torch and the task imported), the RL
library imported, the model compiled, the physics backend up (MuJoCo Warp imported, initialised,
model and data on the device), the first physics reset, the env built, the rsl_rl runner built,
the first env step returned and the first training iteration done. A tree without milestones
gives only the printed start-up and the process wall time. A second table gives each phase's
median: the seconds spent reaching each milestone from the one before (the first from the process
start), and from the first iteration to the process's end (one iteration's end, the checkpoint
save and the interpreter's exit). Then one extra process
per variant under ``python -X importtime`` gives the import cost grouped by package (a module's own
time, summed over the first two parts of its name). Each run also reports the modules Python
compiled from source (no cached bytecode: a fresh install without ``.pyc`` pays this once) and the
Warp kernel modules written to the kernel cache during the run (compiled, not loaded from cache).
"""

from __future__ import annotations

import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
from collections import defaultdict

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
MILESTONES_PREFIX = "[simlab] Start-up milestones (s since the process started):"
STARTUP_LINE = re.compile(r"after ([0-9.]+) s of start-up")

# Runs in the child before simlab: reports (at exit) what the import system and Warp did.
CHILD = r"""
import atexit, json, os, runpy, sys, time
_report = os.environ.pop("STARTUP_COST_REPORT")
_started = time.time()

def _write_report():
    sources = [m for m in list(sys.modules.values()) if str(getattr(m, "__file__", None) or "").endswith(".py")]
    caches = [(m.__name__, getattr(m, "__cached__", None)) for m in sources]
    from_source = [name for name, cache in caches if isinstance(cache, str) and not os.path.exists(cache)]
    info = {"modules": len(sys.modules), "compiled_from_source": len(from_source),
            "from_source_examples": from_source[:5], "dont_write_bytecode": sys.dont_write_bytecode,
            "dynamo_imported": "torch._dynamo" in sys.modules}
    wp = sys.modules.get("warp")
    if wp is not None:
        folder = wp.config.kernel_cache_dir
        info["warp_kernel_cache_dir"] = folder
        if folder and os.path.isdir(folder):
            entries = [os.path.join(folder, e) for e in os.listdir(folder)]
            info["warp_kernel_modules_written"] = sum(os.path.getmtime(e) >= _started for e in entries)
            info["warp_kernel_modules_cached"] = len(entries)
    with open(_report, "w") as f:
        json.dump(info, f)

atexit.register(_write_report)
sys.argv = ["simlab", *sys.argv[1:]]
runpy.run_module("simlab", run_name="__main__", alter_sys=True)
"""


def _train_argv(args: argparse.Namespace, log_root: str) -> list[str]:
    argv = ["train", "--task", args.task, "--headless", "--max_iterations", "1", "--verbose"]
    argv += ["--log_root", log_root, "--device", args.device]
    if args.num_envs is not None:
        argv += ["--num_envs", str(args.num_envs)]
    return argv + list(args.overrides)


def _variant_env(variant: dict) -> dict[str, str]:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([variant["tree"], *filter(None, [os.environ.get("PYTHONPATH")])])
    for name, value in variant["env"].items():  # None unsets
        if value is None:
            env.pop(name, None)
        else:
            env[name] = value
    return env


def run_once(variant: dict, args: argparse.Namespace, log_root: str) -> dict:
    """One fresh ``simlab train`` process: wall time, milestones, printed start-up, child report."""
    with tempfile.NamedTemporaryFile(suffix=".json", delete=False) as f:
        report = f.name
    env = _variant_env(variant)
    env["STARTUP_COST_REPORT"] = report
    cmd = [sys.executable, "-c", CHILD, *_train_argv(args, log_root)]
    start = time.perf_counter()
    out = subprocess.run(cmd, env=env, cwd=log_root, capture_output=True, text=True)
    wall = time.perf_counter() - start
    if out.returncode != 0:
        raise RuntimeError(
            f"{variant['name']}: simlab train failed ({out.returncode}):\n{out.stdout[-2000:]}{out.stderr[-3000:]}"
        )
    row: dict = {"wall_s": wall}
    for line in out.stdout.splitlines():
        if line.startswith(MILESTONES_PREFIX):
            for pair in line[len(MILESTONES_PREFIX) :].split(","):
                name, value = pair.strip().rsplit("=", 1)
                row[name] = float(value)
        found = STARTUP_LINE.search(line)
        if found:
            row["printed start-up"] = float(found.group(1))
    try:
        with open(report) as f:
            row["child"] = json.load(f)
    except (OSError, ValueError):
        row["child"] = {}
    finally:
        if os.path.exists(report):
            os.remove(report)
    return row


def import_costs(variant: dict, args: argparse.Namespace, log_root: str) -> dict[str, float]:
    """Seconds of import per package (first two parts of the module name), from ``-X importtime``."""
    env = _variant_env(variant)
    env["STARTUP_COST_REPORT"] = os.devnull
    cmd = [sys.executable, "-X", "importtime", "-c", CHILD, *_train_argv(args, log_root)]
    out = subprocess.run(cmd, env=env, cwd=log_root, capture_output=True, text=True)
    groups: dict[str, float] = defaultdict(float)
    for line in out.stderr.splitlines():
        found = re.match(r"import time:\s+(\d+) \|\s+\d+ \|\s*(\S+)", line)
        if found:
            groups[".".join(found.group(2).split(".")[:2])] += int(found.group(1)) / 1e6
    return dict(groups)


MILESTONES = (
    "command",
    "configs",
    "library",
    "model compiled",
    "physics backend",
    "physics reset",
    "env",
    "runner",
    "first env step",
    "first iteration",
)
METRICS = (
    "configs",
    "library",
    "model compiled",
    "physics backend",
    "physics reset",
    "env",
    "runner",
    "first env step",
    "first iteration",
    "printed start-up",
    "wall_s",
)


def phase_seconds(row: dict) -> dict[str, float]:
    """Seconds spent reaching each milestone from the one before (the first from the process
    start), and after the first iteration to the process's end (the iteration's end, the save,
    the interpreter's exit)."""
    spent, before = {}, 0.0
    for name in MILESTONES:
        if name in row:
            spent[name] = row[name] - before
            before = row[name]
    if spent:
        spent["to the process end"] = row["wall_s"] - before
    return spent


def print_phase_table(runs: dict[str, list[dict]]) -> None:
    """Median seconds of each start-up phase per variant, and the first variant's over the others'."""
    per_run = {name: [phase_seconds(row) for row in rows] for name, rows in runs.items()}
    names = [p for p in (*MILESTONES, "to the process end") if any(p in r for rows in per_run.values() for r in rows)]
    if not names:
        return
    medians = {
        variant: {p: statistics.median(r[p] for r in rows) for p in names if all(p in r for r in rows)}
        for variant, rows in per_run.items()
    }
    first, others = next(iter(medians)), list(medians)[1:]
    columns = list(medians) + [f"{first}/{name}" for name in others]
    width = max(16, *(len(c) for c in columns))
    print("\nper phase: median s spent reaching each milestone from the one before")
    print(f"{'phase':>18} | " + " | ".join(f"{c:>{width}}" for c in columns))
    for p in names:
        cells = [f"{medians[v][p]:{width}.2f}" if p in medians[v] else f"{'-':>{width}}" for v in medians]
        for name in others:
            both = p in medians[first] and p in medians[name] and medians[name][p] > 0
            cells.append(f"{medians[first][p] / medians[name][p]:{width}.2f}" if both else f"{'-':>{width}}")
        print(f"{p:>18} | " + " | ".join(cells))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="simlab bench startup", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--task", default="simlab/Cartpole-v0")
    parser.add_argument("--device", default="cpu", help="cpu or cuda:N")
    parser.add_argument("--num_envs", type=int, default=None, help="default: the task's")
    parser.add_argument("--runs", type=int, default=5, help="fresh processes per variant")
    parser.add_argument("--before", default=None, help="a folder holding an older simlab package to compare with")
    parser.add_argument("--pycache_prefix", default=None, help="add a variant with PYTHONPYCACHEPREFIX=this folder")
    parser.add_argument("--no_bytecode_variant", action="store_true", help="add a variant that compiles from source")
    parser.add_argument("--top", type=int, default=12, help="packages listed by import cost")
    parser.add_argument("--json", default=None, help="write the runs to this file")
    parser.add_argument("overrides", nargs="*", help="env.x=... / agent.y=... words passed to simlab train")
    args = parser.parse_args(argv)

    variants = [{"name": "now", "tree": ROOT, "env": {}}]
    if args.pycache_prefix:
        prefix = os.path.abspath(args.pycache_prefix)
        cached = {"PYTHONPYCACHEPREFIX": prefix, "PYTHONDONTWRITEBYTECODE": None}
        variants.append({"name": "pycache prefix", "tree": ROOT, "env": cached})
    if args.before:
        variants.append({"name": "before", "tree": os.path.abspath(args.before), "env": {}})
    with tempfile.TemporaryDirectory() as log_root, tempfile.TemporaryDirectory() as empty:
        if args.no_bytecode_variant:
            uncached = {"PYTHONPYCACHEPREFIX": empty, "PYTHONDONTWRITEBYTECODE": "1"}
            variants.append({"name": "no bytecode", "tree": ROOT, "env": uncached})
        runs: dict[str, list[dict]] = {v["name"]: [] for v in variants}
        for r in range(args.runs):
            for v in variants:
                row = run_once(v, args, log_root)
                runs[v["name"]].append(row)
                shown = ", ".join(f"{k} {row[k]:.2f}" for k in METRICS if k in row)
                print(f"round {r + 1} {v['name']:>16}: {shown}", flush=True)
        imports = {v["name"]: import_costs(v, args, log_root) for v in variants}

    print(f"\n{args.task} on {args.device}, {args.runs} fresh processes per variant (s since process start)")
    medians = {
        name: {k: statistics.median(row[k] for row in rows) for k in METRICS if all(k in row for row in rows)}
        for name, rows in runs.items()
    }
    first = variants[0]["name"]
    others = list(medians)[1:]
    columns = list(medians) + [f"{first}/{name}" for name in others]
    width = max(16, *(len(c) for c in columns))
    print(f"{'median s':>18} | " + " | ".join(f"{c:>{width}}" for c in columns))
    for k in METRICS:
        cells = [f"{medians[name][k]:{width}.2f}" if k in medians[name] else f"{'-':>{width}}" for name in medians]
        for name in others:
            both = k in medians[first] and k in medians[name]
            cells.append(f"{medians[first][k] / medians[name][k]:{width}.2f}" if both else f"{'-':>{width}}")
        print(f"{k:>18} | " + " | ".join(cells))
    print_phase_table(runs)
    for name, rows in runs.items():
        child = rows[0]["child"]
        compiled = [row["child"].get("compiled_from_source") for row in rows]
        written = [row["child"].get("warp_kernel_modules_written") for row in rows]
        print(
            f"{name}: first iteration per run {[round(row.get('first iteration', float('nan')), 2) for row in rows]}; "
            f"modules compiled from source per run {compiled} (of {child.get('modules')}); "
            f"torch._dynamo imported by the end: {child.get('dynamo_imported')}"
        )
        if "warp_kernel_cache_dir" in child:
            print(
                f"{name}: Warp kernel cache {child['warp_kernel_cache_dir']}: "
                f"{child.get('warp_kernel_modules_cached')} modules; written (compiled) per run {written}"
            )
    print("\nimport time by package (s, -X importtime, one extra process per variant):")
    for name, groups in imports.items():
        top = sorted(groups.items(), key=lambda kv: -kv[1])[: args.top]
        print(f"{name:>16}: total {sum(groups.values()):.2f}; " + ", ".join(f"{k} {v:.2f}" for k, v in top))
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"args": vars(args), "runs": runs, "medians": medians, "imports": imports}, f, indent=2)
        print(f"wrote {args.json}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
