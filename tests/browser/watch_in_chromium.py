#!/usr/bin/env python3
"""`prism watch` end to end in headless Chromium (run by .ci/run through watch_in_chromium.sh).

    watch_in_chromium.py PRISM_BINARY --screenshot OUT.png [--deadline SECONDS]

Writes a small scene (a red sphere under a white sky) to a fresh directory, starts `prism watch` on it (a free
port), opens the viewer page through the DevTools protocol (check_page.py's client) and checks, each within the
deadline:
1. the first image arrives and is red;
2. the sphere's colour is edited to green in the file: the displayed image turns green;
3. a typo is saved: the page shows the error line (file:line:column) over the last image;
4. the typo is fixed: the error goes and a new image arrives;
5. clicking a pixel shows its linear RGB and sample count;
and that the console stayed clean. Leaves a screenshot of the viewer (after step 5) at OUT.png and prints the
measured times.
"""
import argparse
import base64
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
import urllib.parse
import urllib.request

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_page import CHROMIUM_FLAGS, DevTools  # noqa: E402

SCENE = """(
    camera: (eye: (0, 1.2, 4), target: (0, 0.2, 0), up: (0, 1, 0), fov: 40, size: (160, 120)),
    render: (integrator: envlight, spp: 64),
    materials: {{ "paint": Lambert(albedo: {albedo}), "ground": Lambert(albedo: (0.5, 0.5, 0.5)) }},
    entities: [
        (shape: Sphere(), material: "paint", transform: [Translate((0, 0.5, 0))]),
        (shape: Quad(), material: "ground", transform: [Translate((0, -0.5, 0)), Rotate(axis: (1, 0, 0), degrees: -90), UniformScale(8)]),
        (light: Environment(radiance: (1, 1, 1))),
    ],
)
"""
RED, GREEN = "(0.8, 0.1, 0.1)", "(0.1, 0.8, 0.1)"

# The image's centre pixel (on the sphere) as "mean".
STATE = "JSON.stringify({frames: prismViewer.frames, error: prismViewer.error, " \
        "mean: prismViewer.frame && (f => { const i = 3 * ((f.height >> 1) * f.width + (f.width >> 1)); " \
        "return [f.rgb[i], f.rgb[i + 1], f.rgb[i + 2]]; })(prismViewer.frame), " \
        "shown: getComputedStyle(document.getElementById('error')).display, " \
        "errorText: document.getElementById('error').textContent, " \
        "status: prismViewer.state && prismViewer.state.status, pixel: document.getElementById('pixel').textContent})"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("prism")
    ap.add_argument("--screenshot", required=True)
    ap.add_argument("--chromium", default=shutil.which("chromium") or "/usr/bin/chromium")
    ap.add_argument("--deadline", type=float, default=10.0)
    a = ap.parse_args()
    work = tempfile.mkdtemp(prefix="prism-watch-")
    scene = os.path.join(work, "scene.ron")
    with open(scene, "w") as f:
        f.write(SCENE.format(albedo=RED))
    watch = subprocess.Popen([os.path.abspath(a.prism), "watch", scene, "--port", "0"], stderr=subprocess.PIPE, text=True)
    profile = tempfile.mkdtemp(prefix="prism-chromium-")
    browser = None
    failures, times = [], {}
    try:
        url = None
        end = time.time() + 30
        while url is None and time.time() < end:
            line = watch.stderr.readline()
            if not line and watch.poll() is not None:
                sys.exit(f"watch check: prism watch exited with {watch.returncode}")
            if " at http://" in line:
                url = line.split(" at ", 1)[1].split()[0]
        if url is None:
            sys.exit("watch check: prism watch printed no address")
        browser = subprocess.Popen([a.chromium, *CHROMIUM_FLAGS, f"--user-data-dir={profile}", "about:blank"],
                                   stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        ws_url = None
        while ws_url is None and time.time() < end:
            line = browser.stderr.readline()
            if "DevTools listening on " in line:
                ws_url = line.split("DevTools listening on ", 1)[1].strip()
        if ws_url is None:
            sys.exit("watch check: chromium did not start DevTools")
        port = urllib.parse.urlparse(ws_url).port
        targets = json.load(urllib.request.urlopen(f"http://127.0.0.1:{port}/json/list", timeout=30))
        dt = DevTools(next(t for t in targets if t.get("type") == "page")["webSocketDebuggerUrl"], 30)
        for domain in ("Page", "Runtime", "Log"):
            dt.call(f"{domain}.enable")
        dt.call("Emulation.setDeviceMetricsOverride", width=900, height=640, deviceScaleFactor=1, mobile=False)
        dt.call("Page.navigate", url=url)
        dt.wait_for("Page.loadEventFired", 30)

        def state():
            return json.loads(dt.call("Runtime.evaluate", expression=STATE, returnByValue=True)["result"]["value"])

        def until(what, test):
            t0 = time.time()
            while time.time() - t0 < a.deadline:
                s = state()
                if test(s):
                    times[what] = time.time() - t0
                    return s
                time.sleep(0.02)
            failures.append(f"{what}: not within {a.deadline} s (last state {state()})")
            return None

        def save(albedo, typo=False):
            text = SCENE.format(albedo=albedo)
            if typo:
                text = text.replace("Lambert(", "Lambrt(")
            tmp = scene + ".tmp"
            with open(tmp, "w") as f:
                f.write(text)
            os.replace(tmp, scene)  # as editors save: a new file renamed over the old one

        s = until("first image", lambda s: s["frames"] > 0 and s["mean"] and s["mean"][0] > 2 * s["mean"][1])
        if s:
            frames = s["frames"]
            save(GREEN)
            s = until("colour edit shown", lambda s: s["mean"] and s["mean"][1] > 2 * s["mean"][0])
        if s:
            frames = s["frames"]
            save(GREEN, typo=True)
            s = until("error line shown", lambda s: s["error"] and s["shown"] == "block" and "scene.ron:" in s["errorText"])
            if s and s["frames"] < frames:
                failures.append("the last good image was dropped with the error")
        if s:
            frames = s["frames"]
            save(GREEN)
            s = until("recovered", lambda s: not s["error"] and s["shown"] == "none" and s["frames"] > frames
                      and s["status"] == "done")
        if s:
            dt.call("Input.dispatchMouseEvent", type="mousePressed", x=330, y=330, button="left", clickCount=1)
            dt.call("Input.dispatchMouseEvent", type="mouseReleased", x=330, y=330, button="left", clickCount=1)
            until("pixel readout", lambda s: "samples" in s["pixel"] and "RGB" in s["pixel"])
        shot = dt.call("Page.captureScreenshot", format="png")
        with open(a.screenshot, "wb") as f:
            f.write(base64.b64decode(shot["data"]))
        for e in dt.events:
            m, p = e["method"], e.get("params", {})
            if m == "Runtime.consoleAPICalled" and p.get("type") in ("error", "assert"):
                failures.append("console error: " + json.dumps(p.get("args", [])))
            elif m == "Runtime.exceptionThrown":
                failures.append("uncaught exception: " + p.get("exceptionDetails", {}).get("text", "?"))
            elif m == "Log.entryAdded" and p.get("entry", {}).get("level") == "error":
                failures.append("browser log error: " + p["entry"].get("text", "?"))
        print("watch check: " + ", ".join(f"{k} {v:.2f} s" for k, v in times.items())
              + f"; {len(failures)} failure(s); screenshot {a.screenshot}")
    finally:
        if browser:
            browser.terminate()
            try:
                browser.wait(timeout=10)
            except subprocess.TimeoutExpired:
                browser.kill()
        watch.terminate()
        try:
            watch.wait(timeout=10)
        except subprocess.TimeoutExpired:
            watch.kill()
        shutil.rmtree(profile, ignore_errors=True)
        shutil.rmtree(work, ignore_errors=True)
    for f in failures:
        print("watch check: FAIL: " + f)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
