#!/usr/bin/python3
"""Drives the capture console's page in headless Chromium over the DevTools protocol (Debian's
python3-websocket), in real time: the page's own scripted operator (#operator=N) presses its
buttons; this script records every script error and console.error, takes screenshots when asked,
and prints one JSON object: the operator's record, the errors, the screenshots.

Usage: console_browser.py URL [--operator N] [--calibration C] [--screenshots DIR --at K,K,...]
       [--timeout S]
--at: screenshots once K flash shots are on the page (and one at the end).
"""
import argparse
import base64
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import urllib.request

import websocket


class Page:
    def __init__(self, ws_url):
        self.ws = websocket.create_connection(ws_url, timeout=30, suppress_origin=True)
        self.next_id = 0
        self.errors = []

    def call(self, method, **params):
        self.next_id += 1
        self.ws.send(json.dumps({"id": self.next_id, "method": method, "params": params}))
        while True:
            message = json.loads(self.ws.recv())
            self.note(message)
            if message.get("id") == self.next_id:
                if "error" in message:
                    raise RuntimeError(f"{method}: {message['error']}")
                return message.get("result", {})

    def note(self, message):
        method, params = message.get("method"), message.get("params", {})
        if method == "Runtime.exceptionThrown":
            details = params.get("exceptionDetails", {})
            self.errors.append("exception: " + details.get("exception", {}).get("description", details.get("text", "")))
        elif method == "Runtime.consoleAPICalled" and params.get("type") in ("error", "assert"):
            self.errors.append("console.error: " + " ".join(str(a.get("value", a.get("description", ""))) for a in params.get("args", [])))
        elif method == "Log.entryAdded" and params.get("entry", {}).get("level") == "error":
            entry = params["entry"]
            if "favicon.ico" not in entry.get("url", ""):
                self.errors.append("log: " + entry.get("text", "") + " " + entry.get("url", ""))

    def evaluate(self, expression):
        result = self.call("Runtime.evaluate", expression=expression, returnByValue=True)
        return result.get("result", {}).get("value")

    def screenshot(self, path):
        data = self.call("Page.captureScreenshot", format="png")["data"]
        with open(path, "wb") as out:
            out.write(base64.b64decode(data))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("url")
    parser.add_argument("--operator", type=int, default=0)
    parser.add_argument("--calibration", type=int, default=0)
    parser.add_argument("--screenshots", default="")
    parser.add_argument("--at", default="")
    parser.add_argument("--timeout", type=float, default=300)
    args = parser.parse_args()
    profile = tempfile.mkdtemp(prefix="mesocap-chromium-")
    browser = subprocess.Popen(
        ["chromium", "--headless", "--no-sandbox", "--disable-gpu", "--remote-debugging-port=0",
         "--window-size=1920,1080", f"--user-data-dir={profile}", "about:blank"],
        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    try:
        port = None
        deadline = time.time() + 60
        while port is None and time.time() < deadline:
            line = browser.stderr.readline()
            if not line and browser.poll() is not None:
                raise RuntimeError("chromium ended before it listened")
            found = re.search(r"DevTools listening on ws://[^:]+:(\d+)/", line)
            if found:
                port = int(found.group(1))
        targets = json.load(urllib.request.urlopen(f"http://127.0.0.1:{port}/json/list"))
        page = Page(next(t for t in targets if t["type"] == "page")["webSocketDebuggerUrl"])
        for domain in ("Runtime", "Log", "Page"):
            page.call(domain + ".enable")
        page.call("Emulation.setDeviceMetricsOverride", width=1920, height=1080, deviceScaleFactor=1, mobile=False)
        hash_part = f"#operator={args.operator}&calibration={args.calibration}" if args.operator else ""
        page.call("Page.navigate", url=args.url + hash_part)
        moments = sorted(int(k) for k in args.at.split(",") if k) if args.screenshots else []
        shots_taken = []
        record = None
        end = time.time() + args.timeout
        while time.time() < end:
            time.sleep(0.25)
            flash_shots = page.evaluate(
                "(() => { try { return state ? state.shots.filter(s => s.kind === 'shot').length : 0 } catch (e) { return 0 } })()") or 0
            while moments and flash_shots >= moments[0]:
                path = os.path.join(args.screenshots, f"console_{moments.pop(0):02d}_shots.png")
                time.sleep(0.5)  # the shot's image and the plot loaded
                page.screenshot(path)
                shots_taken.append(path)
            operator = page.evaluate("document.body ? document.body.dataset.operator || '' : ''")
            if operator or not args.operator:
                record = json.loads(operator) if operator else None
                break
        if args.screenshots:
            time.sleep(0.5)
            path = os.path.join(args.screenshots, "console_finished.png")
            page.screenshot(path)
            shots_taken.append(path)
        page_errors = page.evaluate("document.body.dataset.errors")
        print(json.dumps({"operator": record, "errors": page.errors, "page_errors": page_errors,
                          "screenshots": shots_taken, "timed_out": record is None and bool(args.operator)}))
    finally:
        browser.terminate()
        try:
            browser.wait(10)
        except subprocess.TimeoutExpired:
            browser.kill()
        shutil.rmtree(profile, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
