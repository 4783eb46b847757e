"""Headless Chromium driven over the DevTools protocol, for the tests that look at a web page.

A test waits on what the page shows in real time (screenshots polled until a condition holds), not on
Chromium's ``--virtual-time-budget``: virtual time runs ahead of the page's websocket, so on a slow or
loaded machine a one-shot screenshot catches the page before the server's scene has arrived.
"""

from __future__ import annotations

import base64
import io
import json
import shutil
import socket
import subprocess
import tempfile
import time
import urllib.request
from collections.abc import Callable

import numpy as np

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser") or shutil.which("google-chrome")


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class HeadlessChromium:
    """One browser tab (software WebGL) at ``window`` pixels; use as a context manager."""

    def __init__(self, window: tuple[int, int] = (900, 650), start_timeout_s: float = 60.0):
        self._profile = tempfile.TemporaryDirectory(prefix="simlab-chromium-", ignore_cleanup_errors=True)
        debug_port = free_port()
        self._process = subprocess.Popen(
            [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--use-angle=swiftshader",
             "--enable-unsafe-swiftshader", f"--window-size={window[0]},{window[1]}",
             f"--remote-debugging-port={debug_port}", "--remote-allow-origins=*",
             f"--user-data-dir={self._profile.name}", "about:blank"],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
        )  # fmt: skip
        self._socket = None
        try:
            self._connect(debug_port, window, start_timeout_s)
        except BaseException:
            self.close()  # no browser left behind
            raise

    def _connect(self, debug_port: int, window: tuple[int, int], timeout_s: float) -> None:
        from websockets.sync.client import connect

        deadline = time.monotonic() + timeout_s
        while True:
            try:
                targets = json.loads(urllib.request.urlopen(f"http://127.0.0.1:{debug_port}/json").read())
                page = next(t for t in targets if t["type"] == "page")
                break
            except (OSError, StopIteration, ValueError) as error:
                if time.monotonic() > deadline or self._process.poll() is not None:
                    raise RuntimeError(f"headless Chromium gave no page to drive within {timeout_s} s") from error
                time.sleep(0.2)
        self._socket = connect(page["webSocketDebuggerUrl"], max_size=None, open_timeout=timeout_s)
        self._calls = 0
        # the window's size includes the browser's frame; the page's own size is set here
        self.call(
            "Emulation.setDeviceMetricsOverride", width=window[0], height=window[1], deviceScaleFactor=1, mobile=False
        )

    def call(self, method: str, **params) -> dict:
        """One DevTools command; its result (events that arrive meanwhile are skipped)."""
        self._calls += 1
        self._socket.send(json.dumps({"id": self._calls, "method": method, "params": params}))
        while True:
            reply = json.loads(self._socket.recv(timeout=120))
            if reply.get("id") == self._calls:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply.get("result", {})

    def open(self, url: str, timeout_s: float = 120.0) -> None:
        """Go to ``url`` and wait until its document has loaded (its scripts may still be fetching data)."""
        self.call("Page.navigate", url=url)
        deadline = time.monotonic() + timeout_s
        while True:
            try:  # the tab is briefly detached while the new page's renderer takes over
                if (
                    self.evaluate("location.href") != "about:blank"
                    and self.evaluate("document.readyState") == "complete"
                ):
                    return
            except RuntimeError:
                pass
            if time.monotonic() > deadline:
                raise RuntimeError(f"{url} did not load within {timeout_s} s")
            time.sleep(0.2)

    def screenshot(self, path: str | None = None) -> np.ndarray:
        """The tab as drawn now, RGB; also written to ``path`` as PNG when given."""
        import imageio.v3 as iio

        png = base64.b64decode(self.call("Page.captureScreenshot", format="png")["data"])
        if path is not None:
            with open(path, "wb") as f:
                f.write(png)
        return iio.imread(io.BytesIO(png))[..., :3]

    def screenshot_when(
        self, shows: Callable[[np.ndarray], bool], timeout_s: float, path: str | None = None
    ) -> np.ndarray:
        """Screenshots every half second until one ``shows`` what is wanted, or ``timeout_s``: the last one."""
        deadline = time.monotonic() + timeout_s
        while True:
            image = self.screenshot(path)
            if shows(image) or time.monotonic() > deadline:
                return image
            time.sleep(0.5)

    def evaluate(self, expression: str):
        """A JavaScript expression's value in the page."""
        return self.call("Runtime.evaluate", expression=expression, returnByValue=True).get("result", {}).get("value")

    def close(self) -> None:
        if self._socket is not None:
            self._socket.close()
        self._process.kill()
        self._process.wait(timeout=30)
        self._profile.cleanup()

    def __enter__(self) -> HeadlessChromium:
        return self

    def __exit__(self, *exc) -> None:
        self.close()
