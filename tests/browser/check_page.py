#!/usr/bin/env python3
"""Open a `prism report` page in headless Chromium and check that it rendered, through the Chrome DevTools protocol
(a WebSocket client written with the standard library only, no packages to install).

    check_page.py PAGE.html --screenshot OUT.png [--expect-no-problems] [--min-images N] [--min-charts N]
                  [--pieces HEIGHT]

Checks, after the page's load event:
- every <img> loaded and decoded (complete, naturalWidth > 0), and at least --min-images of them;
- every chart SVG (inside .charts) has curves: <polyline class="curve"> elements, each with at least two points
  and a non-empty bounding box, and every colour bar its gradient; at least --min-charts charts;
- no console error, uncaught exception, failed request or browser log error;
- with --expect-no-problems: no problem box on the page.
Writes a full-page screenshot (1400 CSS pixels wide) and exits non-zero with one line per failure.
"""
import argparse
import base64
import json
import os
import shutil
import socket
import struct
import subprocess
import sys
import tempfile
import time
import urllib.parse
import urllib.request

CHROMIUM_FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--disable-quic",
    "--disable-default-apps",
    "--hide-scrollbars",
    "--remote-debugging-port=0",
]


class WebSocket:
    """The client side of RFC 6455: text frames out (masked), frames in (unmasked), pings answered."""

    def __init__(self, url, timeout):
        u = urllib.parse.urlparse(url)
        self.sock = socket.create_connection((u.hostname, u.port), timeout=timeout)
        key = base64.b64encode(os.urandom(16)).decode()
        self.sock.sendall(
            (
                f"GET {u.path} HTTP/1.1\r\nHost: {u.hostname}:{u.port}\r\nUpgrade: websocket\r\n"
                f"Connection: Upgrade\r\nSec-WebSocket-Key: {key}\r\nSec-WebSocket-Version: 13\r\n\r\n"
            ).encode()
        )
        head = b""
        while b"\r\n\r\n" not in head:
            chunk = self.sock.recv(4096)
            if not chunk:
                raise RuntimeError("DevTools closed the connection during the handshake")
            head += chunk
        status = head.split(b"\r\n", 1)[0]
        if b" 101 " not in status:
            raise RuntimeError(f"DevTools refused the WebSocket: {status.decode(errors='replace')}")
        self.buf = head.split(b"\r\n\r\n", 1)[1]

    def _exact(self, n):
        while len(self.buf) < n:
            chunk = self.sock.recv(max(65536, n - len(self.buf)))
            if not chunk:
                raise RuntimeError("DevTools closed the connection")
            self.buf += chunk
        out, self.buf = self.buf[:n], self.buf[n:]
        return out

    def _frame(self, opcode, payload):
        n = len(payload)
        if n < 126:
            head = struct.pack("!BB", 0x80 | opcode, 0x80 | n)
        elif n < 65536:
            head = struct.pack("!BBH", 0x80 | opcode, 0x80 | 126, n)
        else:
            head = struct.pack("!BBQ", 0x80 | opcode, 0x80 | 127, n)
        mask = os.urandom(4)
        masked = bytes(b ^ mask[i % 4] for i, b in enumerate(payload))
        self.sock.sendall(head + mask + masked)

    def send(self, text):
        self._frame(0x1, text.encode())

    def recv(self):
        message = b""
        while True:
            b0, b1 = self._exact(2)
            opcode, n = b0 & 0x0F, b1 & 0x7F
            if n == 126:
                n = struct.unpack("!H", self._exact(2))[0]
            elif n == 127:
                n = struct.unpack("!Q", self._exact(8))[0]
            mask = self._exact(4) if b1 & 0x80 else None
            payload = self._exact(n)
            if mask:
                payload = bytes(b ^ mask[i % 4] for i, b in enumerate(payload))
            if opcode == 0x9:
                self._frame(0xA, payload)
                continue
            if opcode == 0x8:
                raise RuntimeError("DevTools closed the WebSocket")
            if opcode in (0x0, 0x1, 0x2):
                message += payload
                if b0 & 0x80:
                    return message.decode()


class DevTools:
    def __init__(self, ws_url, timeout):
        self.ws = WebSocket(ws_url, timeout)
        self.next_id = 0
        self.events = []

    def call(self, method, **params):
        self.next_id += 1
        my_id = self.next_id
        self.ws.send(json.dumps({"id": my_id, "method": method, "params": params}))
        while True:
            msg = json.loads(self.ws.recv())
            if msg.get("id") == my_id:
                if "error" in msg:
                    raise RuntimeError(f"{method}: {msg['error']}")
                return msg.get("result", {})
            if "method" in msg:
                self.events.append(msg)

    def wait_for(self, method, timeout):
        end = time.time() + timeout
        while time.time() < end:
            for e in self.events:
                if e["method"] == method:
                    return e
            self.events.append(json.loads(self.ws.recv()))
        raise RuntimeError(f"no {method} within {timeout} s")


# Evaluated in the page after load: what rendered and what did not.
PAGE_CHECK = r"""
(() => {
  const imgs = [...document.images];
  const broken = imgs.filter(i => !(i.complete && i.naturalWidth > 0)).map(i => i.getAttribute('src'));
  const charts = [...document.querySelectorAll('.charts svg')];
  const bad = [];
  let curves = 0;
  charts.forEach((svg, k) => {
    const title = (svg.querySelector('text') || {}).textContent || ('chart ' + k);
    const lines = [...svg.querySelectorAll('polyline.curve')];
    if (lines.length === 0) bad.push(title + ': no curves');
    lines.forEach(p => {
      curves++;
      const n = p.points.numberOfItems;
      const b = p.getBBox();
      if (n < 2 || (b.width === 0 && b.height === 0))
        bad.push(title + ': curve "' + p.dataset.series + '" has ' + n + ' point(s)');
    });
  });
  const bars = [...document.querySelectorAll('svg.bar')];
  bars.forEach(b => { if (!b.querySelector('linearGradient stop')) bad.push('colour bar without its gradient'); });
  return JSON.stringify({
    images: imgs.length, broken, charts: charts.length, curves, bars: bars.length, bad,
    problems: document.querySelectorAll('.problem, section.problems').length,
    height: document.documentElement.scrollHeight,
  });
})()
"""


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("page")
    ap.add_argument("--screenshot", required=True)
    ap.add_argument("--chromium", default=shutil.which("chromium") or "/usr/bin/chromium")
    ap.add_argument("--expect-no-problems", action="store_true")
    ap.add_argument("--min-images", type=int, default=1)
    ap.add_argument("--min-charts", type=int, default=1)
    ap.add_argument("--timeout", type=float, default=60)
    ap.add_argument("--pieces", type=int, default=0, help="also write the page in pieces this tall (OUT-1.png ...)")
    a = ap.parse_args()
    page = os.path.abspath(a.page)
    if not os.path.isfile(page):
        sys.exit(f"browser check: {page} does not exist")
    profile = tempfile.mkdtemp(prefix="prism-chromium-")
    proc = subprocess.Popen(
        [a.chromium, *CHROMIUM_FLAGS, f"--user-data-dir={profile}", "about:blank"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    failures = []
    try:
        ws_url = None
        end = time.time() + a.timeout
        while ws_url is None and time.time() < end:
            line = proc.stderr.readline()
            if not line and proc.poll() is not None:
                sys.exit(f"browser check: chromium exited with {proc.returncode} before DevTools started")
            if "DevTools listening on " in line:
                ws_url = line.split("DevTools listening on ", 1)[1].strip()
        if ws_url is None:
            sys.exit("browser check: chromium did not start DevTools")
        port = urllib.parse.urlparse(ws_url).port
        targets = json.load(urllib.request.urlopen(f"http://127.0.0.1:{port}/json/list", timeout=a.timeout))
        target = next(t for t in targets if t.get("type") == "page")
        dt = DevTools(target["webSocketDebuggerUrl"], a.timeout)
        for domain in ("Page", "Runtime", "Log", "Network"):
            dt.call(f"{domain}.enable")
        dt.call("Emulation.setDeviceMetricsOverride", width=1400, height=900, deviceScaleFactor=1, mobile=False)
        dt.call("Page.navigate", url="file://" + urllib.parse.quote(page))
        dt.wait_for("Page.loadEventFired", a.timeout)
        result = json.loads(dt.call("Runtime.evaluate", expression=PAGE_CHECK, returnByValue=True)["result"]["value"])
        height = min(int(result["height"]), 16384)
        dt.call("Emulation.setDeviceMetricsOverride", width=1400, height=height, deviceScaleFactor=1, mobile=False)
        shot = dt.call("Page.captureScreenshot", format="png", captureBeyondViewport=True)
        with open(a.screenshot, "wb") as f:
            f.write(base64.b64decode(shot["data"]))
        if a.pieces:
            # Pieces by scrolling a viewport of that height: beyond 16384 pixels one capture is cut off.
            full = int(result["height"])
            dt.call("Emulation.setDeviceMetricsOverride", width=1400, height=a.pieces, deviceScaleFactor=1, mobile=False)
            for k, y in enumerate(range(0, full, a.pieces)):
                dt.call("Runtime.evaluate", expression=f"window.scrollTo(0, {y})")
                time.sleep(0.2)
                piece = dt.call("Page.captureScreenshot", format="png")
                with open(a.screenshot.replace(".png", f"-{k + 1}.png"), "wb") as f:
                    f.write(base64.b64decode(piece["data"]))
        for e in dt.events:
            m, p = e["method"], e.get("params", {})
            if m == "Runtime.consoleAPICalled" and p.get("type") in ("error", "assert"):
                failures.append("console error: " + " ".join(str(x.get("value", x.get("description", ""))) for x in p.get("args", [])))
            elif m == "Runtime.exceptionThrown":
                failures.append("uncaught exception: " + p.get("exceptionDetails", {}).get("text", "?"))
            elif m == "Log.entryAdded" and p.get("entry", {}).get("level") == "error":
                failures.append("browser log error: " + p["entry"].get("text", "?"))
            elif m == "Network.loadingFailed":
                failures.append("failed request: " + p.get("errorText", "?"))
        failures += [f"broken image: {src}" for src in result["broken"]]
        failures += result["bad"]
        if result["images"] < a.min_images:
            failures.append(f"only {result['images']} images (expected at least {a.min_images})")
        if result["charts"] < a.min_charts:
            failures.append(f"only {result['charts']} charts (expected at least {a.min_charts})")
        if a.expect_no_problems and result["problems"]:
            failures.append(f"the page reports {result['problems']} problem box(es)")
        print(
            f"browser check: {result['images']} images, {result['charts']} charts with {result['curves']} curves, "
            f"{result['bars']} colour bars, {len(failures)} failure(s); screenshot {a.screenshot} "
            f"(1400x{height})"
        )
    finally:
        proc.terminate()
        try:
            proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            proc.kill()
        shutil.rmtree(profile, ignore_errors=True)
    for f in failures:
        print("browser check: FAIL: " + f)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
