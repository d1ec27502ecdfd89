"""The built site, looked at in a real browser (``make docs-check``).

Serves ``docs/_build/html`` on localhost and opens a few pages in headless Chromium: the
home page, a tutorial with figures, an API page and the command-line page. Each page must
have loaded every image (``naturalWidth > 0`` in the browser, after the page's load event)
and every internal link, stylesheet and script must point at a file of the build and, where it names
one, an anchor of that file. A screenshot of each page goes to ``docs/_build/screenshots``.

Chromium is driven through its DevTools protocol on a pipe (``--remote-debugging-pipe``:
JSON messages ended by a NUL byte on file descriptors 3 and 4), so no browser-automation
package is needed. Run ``python docs/check_site.py --help`` for the options.
"""

from __future__ import annotations

import argparse
import base64
import fcntl
import functools
import http.server
import json
import os
import re
import subprocess
import sys
import tempfile
import threading
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urljoin, urlsplit

DOCS = Path(__file__).resolve().parent
BUILD = DOCS / "_build" / "html"
SCREENSHOTS = DOCS / "_build" / "screenshots"
CHROMIUM = Path("/usr/bin/chromium")

#: the pages looked at, relative to the build: the home page, a tutorial with figures (a
#: rendered notebook), one API page and the command-line page
PAGES = ("index.html", "_generated/tutorials/02_rub_simulation.html",
         "_generated/api/modal.html", "_generated/cli.html")

WIDTH, HEIGHT = 1280, 1600       # px, the screenshots' window

# without these, Chromium waits on the network at start-up on a machine without one
FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--disable-dev-shm-usage", "--remote-debugging-pipe", "about:blank")

# every image made eager, then waited for: below the fold, lazy images would never load
IMAGES_JS = """
Promise.all([...document.images].map(img => {
  img.loading = 'eager';
  return img.decode().catch(() => null).then(() => ({
    src: img.getAttribute('src'), url: img.currentSrc || img.src,
    width: img.naturalWidth}));
}))
"""
LINKS_JS = """
[...document.querySelectorAll('a[href], link[href], script[src]')]
  .map(e => e.href || e.src)
"""


class Browser:
    """Headless Chromium, driven through the DevTools protocol on a pipe."""

    def __init__(self, executable: Path = CHROMIUM, timeout_s: float = 60.0):
        self.timeout_s = timeout_s
        # the child's ends of the pipes, numbered 10 and up so that bash can move them to
        # 3 and 4 without overwriting one with the other
        to_child_r, self._to_child = os.pipe()
        self._from_child, from_child_w = os.pipe()
        ends = [fcntl.fcntl(fd, fcntl.F_DUPFD_CLOEXEC, 10) for fd in (to_child_r, from_child_w)]
        for fd in (to_child_r, from_child_w):
            os.close(fd)
        self._profile = tempfile.TemporaryDirectory(prefix="rubdiag-chromium-")
        args = [*FLAGS[:-1], f"--user-data-dir={self._profile.name}",
                f"--window-size={WIDTH},{HEIGHT}", FLAGS[-1]]
        self.process = subprocess.Popen(
            ["/bin/bash", "-c", f'exec "$0" "$@" 3<&{ends[0]} 4>&{ends[1]}', str(executable),
             *args],
            pass_fds=ends, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        for fd in ends:
            os.close(fd)
        self._reader = os.fdopen(self._from_child, "rb", buffering=0)
        self._buffer = b""
        self._next_id = 0
        self._events: list[dict] = []

    def close(self) -> None:
        try:
            self.call("Browser.close")
        except (OSError, RuntimeError, TimeoutError):
            pass
        try:
            self.process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()
        self._reader.close()
        os.close(self._to_child)
        self._profile.cleanup()

    def __enter__(self) -> Browser:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def _message(self) -> dict:
        """The next message from the browser (a reply or an event)."""
        timer = threading.Timer(self.timeout_s, self.process.kill)   # a hung browser dies
        timer.start()
        try:
            while b"\0" not in self._buffer:
                chunk = self._reader.read(1 << 16)
                if not chunk:
                    raise RuntimeError("Chromium closed its DevTools pipe "
                                       f"(exit status {self.process.poll()})")
                self._buffer += chunk
        finally:
            timer.cancel()
        message, self._buffer = self._buffer.split(b"\0", 1)
        return json.loads(message)

    def call(self, method: str, session: str | None = None, **params) -> dict:
        """Send one command and return its result."""
        self._next_id += 1
        message = {"id": self._next_id, "method": method, "params": params}
        if session:
            message["sessionId"] = session
        os.write(self._to_child, json.dumps(message).encode() + b"\0")
        while True:
            reply = self._message()
            if reply.get("id") == self._next_id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply.get("result", {})
            if "method" in reply:
                self._events.append(reply)

    def wait_for(self, event: str, session: str) -> dict:
        """Wait for an event of the page's session."""
        while True:
            for i, seen in enumerate(self._events):
                if seen["method"] == event and seen.get("sessionId") == session:
                    return self._events.pop(i)
            self._events.append(self._message())

    def open(self, url: str) -> str:
        """A new tab showing ``url``, loaded; its session id."""
        target = self.call("Target.createTarget", url="about:blank")["targetId"]
        session = self.call("Target.attachToTarget", targetId=target, flatten=True)["sessionId"]
        self.call("Page.enable", session)
        self.call("Emulation.setDeviceMetricsOverride", session, width=WIDTH, height=HEIGHT,
                  deviceScaleFactor=1, mobile=False)
        self._events.clear()
        self.call("Page.navigate", session, url=url)
        self.wait_for("Page.loadEventFired", session)
        return session

    def evaluate(self, session: str, expression: str):
        """The value of a JavaScript expression in the page (promises awaited)."""
        result = self.call("Runtime.evaluate", session, expression=expression,
                           awaitPromise=True, returnByValue=True)
        if "exceptionDetails" in result:
            raise RuntimeError(f"{expression!r}: {result['exceptionDetails']}")
        return result["result"].get("value")

    def screenshot(self, session: str, path: Path) -> None:
        data = self.call("Page.captureScreenshot", session, format="png")["data"]
        path.write_bytes(base64.b64decode(data))


class _Anchors(HTMLParser):
    def __init__(self):
        super().__init__()
        self.ids: set[str] = set()

    def handle_starttag(self, tag, attrs):
        for key, value in attrs:
            if key == "id" or (tag == "a" and key == "name"):
                self.ids.add(value)


@functools.cache
def anchors(path: Path) -> frozenset[str]:
    """Every id (and ``<a name>``) of an HTML file."""
    parser = _Anchors()
    parser.feed(path.read_text(encoding="utf-8", errors="replace"))
    return frozenset(parser.ids)


def broken_link(url: str, base: str, build: Path) -> str | None:
    """Why an internal URL of the served build does not resolve, or None if it does (or is
    not internal)."""
    parts = urlsplit(url)
    if not url.startswith(base) or parts.scheme not in ("http", "https"):
        return None
    path = build / unquote(parts.path).lstrip("/")
    if path.is_dir():
        path = path / "index.html"
    if not path.is_file():
        return f"{url}: no file {path.relative_to(build)}"
    fragment = unquote(parts.fragment)
    if fragment and path.suffix == ".html" and fragment not in anchors(path):
        return f"{url}: {path.relative_to(build)} has no anchor #{fragment}"
    return None


def check_page(browser: Browser, base: str, page: str, build: Path,
               screenshots: Path) -> dict:
    """Load one page; its images, broken internal links and screenshot."""
    session = browser.open(urljoin(base, page))
    title = browser.evaluate(session, "document.title")
    images = browser.evaluate(session, IMAGES_JS)
    links = sorted(set(browser.evaluate(session, LINKS_JS)))
    shot = screenshots / (re.sub(r"[^\w.-]+", "_", page.removesuffix(".html")) + ".png")
    browser.screenshot(session, shot)
    if images:               # and one with the first figure at the top of the window
        browser.evaluate(session, "document.images[0].scrollIntoView()")
        browser.screenshot(session, shot.with_name(shot.stem + "-figure.png"))
    problems = [f"image {img['src']} did not load (naturalWidth 0)"
                for img in images if not img["width"] > 0]
    problems += [why for why in (broken_link(url, base, build) for url in links) if why]
    return {"page": page, "title": title, "images": len(images), "links": len(links),
            "screenshot": shot, "problems": problems}


class _QuietHandler(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args):
        pass


def check_site(build: Path = BUILD, pages=PAGES, screenshots: Path = SCREENSHOTS,
               executable: Path = CHROMIUM) -> list[dict]:
    """Serve ``build`` on localhost and look at ``pages`` in headless Chromium.

    Parameters
    ----------
    build : Path
        The built HTML site (``make docs``).
    pages : sequence of str
        The pages to open, relative to ``build``.
    screenshots : Path
        Folder the screenshots are written to, one PNG per page.
    executable : Path
        The Chromium binary.

    Returns
    -------
    list of dict
        Per page: ``page``, ``title``, ``images`` (count), ``links`` (count of distinct
        links and sources), ``screenshot`` (path) and ``problems`` (the images that did not
        load and the internal links that do not resolve; empty when the page is sound).
    """
    screenshots.mkdir(parents=True, exist_ok=True)
    handler = functools.partial(_QuietHandler, directory=str(build))
    with http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler) as server:
        threading.Thread(target=server.serve_forever, daemon=True).start()
        base = f"http://127.0.0.1:{server.server_address[1]}/"
        try:
            with Browser(executable) as browser:
                return [check_page(browser, base, page, build, screenshots) for page in pages]
        finally:
            server.shutdown()


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--build", type=Path, default=BUILD,
                        help="the built site (default: %(default)s)")
    parser.add_argument("--screenshots", type=Path, default=SCREENSHOTS,
                        help="where the screenshots go (default: %(default)s)")
    parser.add_argument("--chromium", type=Path, default=CHROMIUM,
                        help="the Chromium binary (default: %(default)s)")
    args = parser.parse_args(argv)
    if not (args.build / "index.html").is_file():
        parser.error(f"--build: no index.html in {args.build}; run make docs first")
    if not args.chromium.is_file():
        parser.error(f"--chromium: {args.chromium} not found (apt-get install chromium)")
    failed = False
    for seen in check_site(args.build, PAGES, args.screenshots, args.chromium):
        print(f"{seen['page']}: {seen['images']} images, {seen['links']} links, "
              f"{len(seen['problems'])} problems -> {seen['screenshot']}")
        for problem in seen["problems"]:
            print(f"  {problem}")
        failed = failed or bool(seen["problems"])
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
