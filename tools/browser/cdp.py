"""A headless Chromium driven over the DevTools protocol, from Python's standard library alone.

Chromium is started with `--remote-debugging-pipe`: it reads protocol messages (JSON, each ended
by a NUL byte) on its file descriptor 3 and writes its answers and events on descriptor 4, so no
WebSocket client and no network port are needed. One page is opened; everything that page
reports as an error is kept: uncaught exceptions, `console.error`, the browser's own error log
(a resource that failed to load, a parse error) and any request that is not to a `file:`,
`data:` or `about:` address (a figure or an animation must need no network).
"""

import json
import os
import queue
import shutil
import subprocess
import tempfile
import threading
import time

FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--disable-extensions",
    "--remote-debugging-pipe",
]


class BrowserError(Exception):
    """The browser did not answer, or answered a command with an error."""


def find_chromium():
    """The Chromium executable on the PATH, or None."""
    for name in ("chromium", "chromium-browser", "google-chrome"):
        path = shutil.which(name)
        if path:
            return path
    return None


class Browser:
    """One headless Chromium with one page (a tab), driven through the protocol pipe."""

    def __init__(self, executable, width=1000, height=800):
        self.profile = tempfile.mkdtemp(prefix="lagrange-chromium-")
        # Descriptors at 10 and above, so that placing them at 3 and 4 in the child never
        # overwrites one with the other.
        to_child_r, to_child_w = (os.dup(fd) for fd in os.pipe())
        from_child_r, from_child_w = (os.dup(fd) for fd in os.pipe())

        def place_pipes():
            os.dup2(to_child_r, 3)
            os.dup2(from_child_w, 4)
            os.set_inheritable(3, True)
            os.set_inheritable(4, True)

        self.process = subprocess.Popen(
            [executable, *FLAGS, f"--user-data-dir={self.profile}",
             f"--window-size={width},{height}", "about:blank"],
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            preexec_fn=place_pipes,
            pass_fds=(3, 4),
        )
        os.close(to_child_r)
        os.close(from_child_w)
        self.writer = os.fdopen(to_child_w, "wb")
        self.reader = os.fdopen(from_child_r, "rb")
        self.next_id = 0
        self.answers = {}
        self.events = queue.Queue()
        self.lock = threading.Condition()
        threading.Thread(target=self._read, daemon=True).start()
        target = self.command("Target.createTarget", {"url": "about:blank"})["targetId"]
        self.session = self.command(
            "Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
        for domain in ("Runtime", "Log", "Page", "Network"):
            self.command(f"{domain}.enable", session=True)
        self.errors = []

    def _read(self):
        buffer = b""
        while True:
            chunk = self.reader.read1(1 << 16)
            if not chunk:
                with self.lock:
                    self.answers[None] = {"error": {"message": "the browser closed its pipe"}}
                    self.lock.notify_all()
                return
            buffer += chunk
            while b"\0" in buffer:
                raw, buffer = buffer.split(b"\0", 1)
                message = json.loads(raw)
                if "id" in message:
                    with self.lock:
                        self.answers[message["id"]] = message
                        self.lock.notify_all()
                else:
                    self.events.put(message)

    def command(self, method, params=None, session=False, timeout=30.0):
        """Sends one command and waits for its answer's `result`."""
        self.next_id += 1
        message = {"id": self.next_id, "method": method, "params": params or {}}
        if session:
            message["sessionId"] = self.session
        self.writer.write(json.dumps(message).encode() + b"\0")
        self.writer.flush()
        deadline = time.monotonic() + timeout
        with self.lock:
            while self.next_id not in self.answers and None not in self.answers:
                left = deadline - time.monotonic()
                if left <= 0:
                    raise BrowserError(f"no answer to {method} in {timeout} s")
                self.lock.wait(left)
            answer = self.answers.pop(self.next_id, None) or self.answers[None]
        if "error" in answer:
            raise BrowserError(f"{method}: {answer['error'].get('message')}")
        return answer.get("result", {})

    def _drain(self, until=None, timeout=0.0):
        """Takes the events waiting (until one named `until` arrives, if given), keeping the
        errors among them. Returns whether `until` arrived."""
        deadline = time.monotonic() + timeout
        while True:
            left = deadline - time.monotonic()
            try:
                event = self.events.get(timeout=max(left, 0.0)) if until else self.events.get_nowait()
            except queue.Empty:
                return False
            self._keep_error(event)
            if until and event.get("method") == until:
                return True

    def _keep_error(self, event):
        method, params = event.get("method"), event.get("params", {})
        if method == "Runtime.exceptionThrown":
            details = params.get("exceptionDetails", {})
            text = details.get("exception", {}).get("description") or details.get("text")
            self.errors.append(f"uncaught exception: {text}")
        elif method == "Runtime.consoleAPICalled" and params.get("type") in ("error", "assert"):
            args = " ".join(str(a.get("value", a.get("description", ""))) for a in params.get("args", []))
            self.errors.append(f"console.{params['type']}: {args}")
        elif method == "Log.entryAdded" and params.get("entry", {}).get("level") == "error":
            self.errors.append(f"browser log: {params['entry'].get('text')}")
        elif method == "Network.requestWillBeSent":
            url = params.get("request", {}).get("url", "")
            if not url.startswith(("file:", "data:", "about:")):
                self.errors.append(f"network request: {url}")

    def open(self, path, settle=0.3):
        """Loads a local file and waits for its load event (and `settle` seconds more, for its
        scripts); the errors seen while loading are then in `self.errors`."""
        self._drain()
        self.errors = []
        url = "file://" + os.path.abspath(path)
        result = self.command("Page.navigate", {"url": url}, session=True)
        if result.get("errorText"):
            self.errors.append(f"navigation: {result['errorText']}")
            return
        if not self._drain(until="Page.loadEventFired", timeout=30.0):
            self.errors.append(f"{path}: no load event in 30 s")
        time.sleep(settle)
        self._drain()

    def evaluate(self, expression):
        """The value of a JavaScript expression in the page (promises awaited)."""
        result = self.command(
            "Runtime.evaluate",
            {"expression": expression, "returnByValue": True, "awaitPromise": True},
            session=True,
        )
        self._drain()
        if "exceptionDetails" in result:
            details = result["exceptionDetails"]
            text = details.get("exception", {}).get("description") or details.get("text")
            raise BrowserError(f"script failed: {text}")
        return result.get("result", {}).get("value")

    def close(self):
        try:
            self.command("Browser.close", timeout=5.0)
        except (BrowserError, OSError):
            pass
        try:
            self.process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
        shutil.rmtree(self.profile, ignore_errors=True)
