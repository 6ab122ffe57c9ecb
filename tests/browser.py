"""Headless Chromium driven over the DevTools protocol, with Python's standard library only.

Chromium is started with ``--remote-debugging-pipe``: it reads protocol commands from its file descriptor 3 and
writes replies and events to 4, each message one JSON text ended by a NUL byte. :class:`Browser` opens one page,
records what the page does that a test must see (script errors and exceptions, console errors, every network
request), and offers the few commands the report's tests need: open a file, evaluate an expression (awaiting a
Promise), move the mouse, measure the layout, take a screenshot.

``Runtime.evaluate`` runs outside the page's Content-Security-Policy, so a test can read the page without
injecting a ``<script>`` that the policy would (rightly) refuse.
"""

from __future__ import annotations

import base64
import json
import os
import select
import shutil
import tempfile
import time
from pathlib import Path

CHROMIUM = os.environ.get("ROUGHLIGHT_CHROMIUM", "/usr/bin/chromium")
FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking", "--no-first-run",
         "--no-default-browser-check", "--disable-component-update", "--disable-sync", "--disable-quic",
         "--remote-debugging-pipe")


class BrowserError(RuntimeError):
    """The browser stopped, timed out, or answered a command with an error."""


class Browser:
    """One headless Chromium with one page (a context manager).

    Parameters
    ----------
    width, height : the page's viewport, CSS pixels.
    workdir : where the browser's throw-away profile is made (a temporary directory when None).
    """

    def __init__(self, width: int = 1280, height: int = 900, workdir=None):
        if not (os.path.exists(CHROMIUM) and os.access(CHROMIUM, os.X_OK)):
            raise BrowserError(f"no Chromium at {CHROMIUM}: `make test` installs Debian's chromium")
        self.profile = tempfile.mkdtemp(prefix="chromium-profile-", dir=workdir)
        to_browser_r, self._to_browser = os.pipe()
        self._from_browser, from_browser_w = os.pipe()
        log = os.open(os.path.join(self.profile, "chromium.log"), os.O_WRONLY | os.O_CREAT, 0o644)
        actions = [(os.POSIX_SPAWN_DUP2, to_browser_r, 3), (os.POSIX_SPAWN_DUP2, from_browser_w, 4),
                   (os.POSIX_SPAWN_DUP2, log, 1), (os.POSIX_SPAWN_DUP2, log, 2)]
        argv = [CHROMIUM, *FLAGS, f"--user-data-dir={self.profile}", f"--window-size={width},{height}",
                "about:blank"]
        self.pid = os.posix_spawn(CHROMIUM, argv, os.environ, file_actions=actions)
        for fd in (to_browser_r, from_browser_w, log):
            os.close(fd)
        self._buffer, self._next_id, self.events = b"", 0, []
        self.session = None
        self.width, self.height = width, height
        target = self.command("Target.createTarget", url="about:blank")["targetId"]
        self.session = self.command("Target.attachToTarget", targetId=target, flatten=True)["sessionId"]
        for domain in ("Page", "Runtime", "Network", "Log"):
            self.command(f"{domain}.enable")
        self.command("Emulation.setDeviceMetricsOverride", width=width, height=height, deviceScaleFactor=1,
                     mobile=False)

    # ------------------------------------------------------------------
    # the protocol

    def _read(self, timeout: float) -> dict:
        deadline = time.monotonic() + timeout
        while b"\0" not in self._buffer:
            left = deadline - time.monotonic()
            if left <= 0:
                raise BrowserError(f"no message from Chromium within {timeout:g} s")
            ready, _, _ = select.select([self._from_browser], [], [], left)
            if ready:
                chunk = os.read(self._from_browser, 1 << 20)
                if not chunk:
                    raise BrowserError("Chromium closed its pipe: " + self.log()[-2000:])
                self._buffer += chunk
        message, self._buffer = self._buffer.split(b"\0", 1)
        return json.loads(message)

    def command(self, method: str, timeout: float = 60.0, **params) -> dict:
        """Send one command to the page (to the browser before the page exists); its result, or raise its error.
        Events that arrive meanwhile are kept in :attr:`events`."""
        self._next_id += 1
        message = {"id": self._next_id, "method": method, "params": params}
        if self.session is not None:
            message["sessionId"] = self.session
        os.write(self._to_browser, json.dumps(message).encode() + b"\0")
        while True:
            reply = self._read(timeout)
            if reply.get("id") == self._next_id:
                if "error" in reply:
                    raise BrowserError(f"{method}: {reply['error']}")
                return reply.get("result", {})
            if "method" in reply:
                self.events.append(reply)

    def wait_for(self, method: str, timeout: float = 60.0) -> dict:
        """Wait for the next event ``method`` (one already received counts); return it."""
        for i, event in enumerate(self.events):
            if event["method"] == method:
                return self.events.pop(i)
        deadline = time.monotonic() + timeout
        while True:
            event = self._read(max(deadline - time.monotonic(), 0.001))
            if event.get("method") == method:
                return event
            if "method" in event:
                self.events.append(event)

    # ------------------------------------------------------------------
    # what the tests do

    def open(self, path, timeout: float = 60.0) -> float:
        """Load a file (or URL) and wait for its ``load`` event; the seconds it took."""
        url = Path(path).resolve().as_uri() if not str(path).startswith(("file:", "http:", "about:", "data:")) \
            else str(path)
        self.events = [e for e in self.events if e["method"] != "Page.loadEventFired"]
        start = time.monotonic()
        self.command("Page.navigate", url=url)
        self.wait_for("Page.loadEventFired", timeout)
        return time.monotonic() - start

    def evaluate(self, expression: str, timeout: float = 60.0):
        """The value of a JavaScript expression in the page (a Promise is awaited), as JSON gives it."""
        result = self.command("Runtime.evaluate", timeout=timeout, expression=expression, awaitPromise=True,
                              returnByValue=True)
        if "exceptionDetails" in result:
            details = result["exceptionDetails"]
            raise BrowserError(f"{expression[:80]}: {details.get('exception', {}).get('description', details)}")
        return result["result"].get("value")

    def mouse_move(self, x: float, y: float) -> None:
        """A real mouse move to viewport coordinates (CSS pixels), as the input pipeline delivers it."""
        self.command("Input.dispatchMouseEvent", type="mouseMoved", x=x, y=y, button="none")

    def click(self, x: float, y: float) -> None:
        """A left click at viewport coordinates."""
        for kind in ("mousePressed", "mouseReleased"):
            self.command("Input.dispatchMouseEvent", type=kind, x=x, y=y, button="left", clickCount=1)

    def screenshot(self, path, full_page: bool = False) -> Path:
        """A PNG of the viewport (or of the whole page) at ``path``."""
        params = {"format": "png"}
        if full_page:
            size = self.command("Page.getLayoutMetrics")["cssContentSize"]
            params.update(captureBeyondViewport=True, clip={"x": 0, "y": 0, "width": self.width,
                                                            "height": size["height"], "scale": 1})
        data = self.command("Page.captureScreenshot", **params)["data"]
        path = Path(path)
        path.write_bytes(base64.b64decode(data))
        return path

    def drain(self, seconds: float = 0.2) -> None:
        """Collect the events that arrive within ``seconds``."""
        deadline = time.monotonic() + seconds
        while True:
            try:
                event = self._read(max(deadline - time.monotonic(), 0.001))
            except BrowserError:
                return
            if "method" in event:
                self.events.append(event)

    def errors(self) -> list[str]:
        """Every script exception, console error and log error the page has raised so far."""
        self.drain()
        out = []
        for e in self.events:
            p = e.get("params", {})
            if e["method"] == "Runtime.exceptionThrown":
                d = p["exceptionDetails"]
                out.append(d.get("exception", {}).get("description") or d.get("text", "exception"))
            elif e["method"] == "Runtime.consoleAPICalled" and p.get("type") in ("error", "assert"):
                out.append(" ".join(str(a.get("value", a.get("description", ""))) for a in p.get("args", [])))
            elif e["method"] == "Log.entryAdded" and p["entry"].get("level") == "error":
                out.append(p["entry"].get("text", ""))
        return out

    def requests(self) -> list[str]:
        """The URL of every network request the page has made so far."""
        self.drain()
        return [e["params"]["request"]["url"] for e in self.events if e["method"] == "Network.requestWillBeSent"]

    def log(self) -> str:
        try:
            return Path(self.profile, "chromium.log").read_text(errors="replace")
        except OSError:
            return ""

    def close(self) -> None:
        try:
            os.kill(self.pid, 15)
            for _ in range(50):
                if os.waitpid(self.pid, os.WNOHANG)[0]:
                    break
                time.sleep(0.1)
            else:
                os.kill(self.pid, 9)
                os.waitpid(self.pid, 0)
        except (ProcessLookupError, ChildProcessError):
            pass
        for fd in (self._to_browser, self._from_browser):
            try:
                os.close(fd)
            except OSError:
                pass
        shutil.rmtree(self.profile, ignore_errors=True)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def read_page(html: str, workdir, script: str, width: int = 1280, height: int = 900):
    """Write the page ``html`` to ``workdir/report.html``, open it in Chromium and return what ``script`` (a
    JavaScript expression) evaluates to there, after checking the page raised no error."""
    path = Path(workdir) / "report.html"
    path.write_text(html, encoding="utf-8")
    with Browser(width, height, workdir=workdir) as browser:
        browser.open(path)
        seen = browser.evaluate(script)
        assert browser.errors() == []
    return seen
