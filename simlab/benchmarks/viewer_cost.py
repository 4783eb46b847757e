"""What the web viewer costs training: `simlab train` headless against `--viewer web` with a client.

    simlab bench viewer --device cpu --tasks simlab/Cartpole-v0 --num_envs 64 --iterations 200
    simlab bench viewer --device cuda --tasks simlab/Cartpole-v0 simlab/Humanoid-Direct-v0

For each task, three trainings with the same seed, in turn: headless; the web viewer open with one
client connected that receives everything a browser would (viser's websocket protocol, read by a
small Python client: the scene, then every pose update); and, with ``--chromium``, the web viewer
with headless Chromium drawing the page on this machine. The figure is each run's training time
(printed by `simlab train`, start-up excluded) against the headless one, repeated ``--repeats``
times. The client run is the remote-browser case the viewer is made for: a person watches a
training server from their own machine, whose drawing costs the server nothing.
"""

from __future__ import annotations

import argparse
import asyncio
import os
import re
import secrets
import shutil
import socket
import subprocess
import sys
import threading
import time

_TOOK = re.compile(r"Training took ([0-9.]+) s")
_URL = re.compile(r"Web viewer: (http://\S+)")
# the viewer's token, given to it as SIMLAB_VIEWER_TOKEN: the clients start before its URL is printed
_TOKEN = secrets.token_urlsafe(32)


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def _camera_message() -> bytes:
    """The viewer-camera message a browser sends when it opens the page (viser's wire format: msgpack)."""
    import msgspec

    camera = {
        "type": "ViewerCameraMessage",
        "wxyz": [1.0, 0.0, 0.0, 0.0],
        "position": [3.0, 3.0, 3.0],
        "fov": 1.0,
        "near": 0.01,
        "far": 1000.0,
        "image_height": 720,
        "image_width": 1280,
        "look_at": [0.0, 0.0, 0.0],
        "up_direction": [0.0, 0.0, 1.0],
    }
    return msgspec.msgpack.encode(camera)


class ViserClient(threading.Thread):
    """Reads every message a viser server sends, as a browser's websocket would, and counts bytes."""

    def __init__(self, port: int):
        super().__init__(daemon=True)
        self.port = port
        self.bytes = 0
        self.messages = 0
        self._stop = threading.Event()

    def run(self) -> None:
        asyncio.run(self._read())

    async def _read(self) -> None:
        import viser
        import websockets

        uri = f"ws://127.0.0.1:{self.port}/?token={_TOKEN}"
        camera = _camera_message()
        protocol = f"viser-v{viser.__version__}"
        for _ in range(300):  # the server starts with the env: retry until it listens
            try:
                async with websockets.connect(uri, subprotocols=[protocol], max_size=None) as ws:
                    await ws.send(camera)  # a browser's first word: viser counts it as a client from then on
                    while not self._stop.is_set():
                        try:
                            message = await asyncio.wait_for(ws.recv(), timeout=0.5)
                        except TimeoutError:
                            continue
                        self.bytes += len(message)
                        self.messages += 1
                    return
            except (OSError, websockets.exceptions.WebSocketException):
                await asyncio.sleep(0.2)

    def stop(self) -> None:
        self._stop.set()


def train(task: str, args: argparse.Namespace, viewer: str) -> tuple[float, str]:
    """One training; ``viewer`` is "headless", "client" or "chromium". Returns (training s, note)."""
    cmd = [sys.executable, "-m", "simlab", "train", "--task", task, "--device", args.device]
    cmd += ["--max_iterations", str(args.iterations), "--log_root", args.log_root, "agent.seed=1"]
    if args.num_envs:
        cmd += ["--num_envs", str(args.num_envs)]
    port = free_port()
    cmd += ["--headless"] if viewer == "headless" else ["--viewer", "web", "--viewer_port", str(port)]
    client, browser = None, None
    if viewer == "client":
        client = ViserClient(port)
        client.start()
    if viewer == "chromium":
        chromium = shutil.which("chromium") or shutil.which("chromium-browser")
        if chromium is None:
            raise SystemExit("--chromium needs Debian's chromium")
        browser = subprocess.Popen(
            [chromium, "--headless", "--no-sandbox", "--disable-gpu-sandbox", f"--remote-debugging-port={free_port()}",
             f"http://127.0.0.1:{port}/?token={_TOKEN}"],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )  # fmt: skip
    try:
        done = subprocess.run(cmd, capture_output=True, text=True, env=dict(os.environ, SIMLAB_VIEWER_TOKEN=_TOKEN))
    finally:
        if client is not None:
            client.stop()
            client.join(timeout=5)
        if browser is not None:
            browser.terminate()
            browser.wait(timeout=30)
    out = done.stdout + done.stderr
    took = _TOOK.search(out)
    if done.returncode != 0 or took is None:
        raise SystemExit(f"training failed ({done.returncode}):\n{out[-3000:]}")
    note = f"client received {client.messages} messages, {client.bytes / 1e6:.1f} MB" if client else ""
    return float(took.group(1)), note


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="simlab bench viewer", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--device", default="cpu")
    parser.add_argument("--tasks", nargs="+", default=["simlab/Cartpole-v0"])
    parser.add_argument("--num_envs", type=int, default=None, help="Default: the task's.")
    parser.add_argument("--iterations", type=int, default=200)
    parser.add_argument("--repeats", type=int, default=2)
    parser.add_argument("--chromium", action="store_true", help="Also run with headless Chromium on the page.")
    parser.add_argument("--log_root", default="/tmp/simlab_viewer_cost")
    args = parser.parse_args(argv)

    kinds = ["headless", "client"] + (["chromium"] if args.chromium else [])
    print("| task | run | training time | vs headless | note |")
    print("| --- | --- | --- | --- | --- |")
    for task in args.tasks:
        times: dict[str, list[float]] = {kind: [] for kind in kinds}
        notes: dict[str, str] = {}
        for _ in range(args.repeats):
            for kind in kinds:  # interleaved: a machine's slow minute hits every kind alike
                took, note = train(task, args, kind)
                times[kind].append(took)
                notes[kind] = note or notes.get(kind, "")
                time.sleep(1.0)
        base = min(times["headless"])
        for kind in kinds:
            best = min(times[kind])
            runs = ", ".join(f"{t:.1f}" for t in times[kind])
            print(f"| {task} | {kind} | {best:.1f} s (runs: {runs}) | {base / best:.2f}x | {notes[kind]} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
