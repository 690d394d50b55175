"""The control door against a real browser (issue 34): a page served from another local
port, in headless Chromium, tries everything a hostile page can (a text/plain POST, a
form, a bodyless POST, a JSON POST, a read, the event stream) and neither acts nor
reads; a DNS-rebinding name for 127.0.0.1 gets no panel; off loopback the panel works
with its token. The door runs in-process (its refusals are counted); the waits are
liveness bounds, never measurements. Skips as tests/test_panel_browser.py does."""

from __future__ import annotations

import contextlib
import http.server
import socket
import threading
from collections.abc import Iterator

import pytest

from tests.browsers import chromium, skip_without_browser
from tests.test_control_security import Door

WAIT = 30.0
REBOUND = "rebound.test"  # a name the browser resolves to 127.0.0.1, as a rebinding page's

skip_without_browser()


@pytest.fixture
def browser() -> Iterator[object]:
    with chromium(f"--host-resolver-rules=MAP {REBOUND} 127.0.0.1", size="1200,900") as d:
        yield d


def _until(driver: object, predicate, message: str):
    from selenium.webdriver.support.ui import WebDriverWait

    return WebDriverWait(driver, WAIT, poll_frequency=0.05).until(predicate, message)


HOSTILE = """<!doctype html><html><body>
<form id="form" method="POST" action="DOOR/api/clock" enctype="text/plain" target="sink">
<input name='{"pause": true, "x": "' value='"}'></form>
<iframe name="sink"></iframe>
<script>
const door = "DOOR";
const out = {};
async function attempt(name, url, init, read) {
  try {
    const r = await fetch(url, init);
    out[name] = read ? "read " + (await r.text()).slice(0, 40) : "sent";
  } catch (e) { out[name] = "refused"; }
}
async function go() {
  await attempt("plain", door + "/api/clock", {method: "POST", mode: "no-cors",
    headers: {"Content-Type": "text/plain"}, body: '{"pause": true}'});
  await attempt("reset", door + "/api/boards/1/reset", {method: "POST", mode: "no-cors"});
  await attempt("world", door + "/api/boards/1/world", {method: "POST", mode: "no-cors",
    headers: {"Content-Type": "text/plain"}, body: '{"words": "X fault plus active"}'});
  await attempt("json", door + "/api/boards/1/world", {method: "POST",
    headers: {"Content-Type": "application/json"},
    body: JSON.stringify({words: "X fault plus active"})});
  await attempt("read", door + "/api/boards/1/traffic", {}, true);
  await attempt("opaque", door + "/api", {mode: "no-cors"}, true);
  document.getElementById("form").submit();
  await new Promise(done => {
    const s = new EventSource(door + "/api/stream");
    s.onmessage = ev => { out.stream = "read " + ev.data.slice(0, 20); s.close(); done(); };
    s.onerror = () => { out.stream = "refused"; s.close(); done(); };
  });
  document.body.dataset.done = JSON.stringify(out);
}
go();
</script></body></html>"""


@contextlib.contextmanager
def _page_server(text: str) -> Iterator[int]:
    """Another local web server (another origin) serving one page."""
    body = text.encode()

    class Page(http.server.BaseHTTPRequestHandler):
        def do_GET(self) -> None:  # noqa: N802 (http.server's name)
            self.send_response(200)
            self.send_header("Content-Type", "text/html")
            self.send_header("Content-Length", str(len(body)))
            self.end_headers()
            self.wfile.write(body)

        def log_message(self, *args: object) -> None:
            pass

    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), Page)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield server.server_address[1]
    finally:
        server.shutdown()
        server.server_close()


def test_a_page_of_another_origin_can_neither_act_nor_read(browser) -> None:
    import json

    from selenium.webdriver.common.by import By

    d = Door(("MAXk-8000",))
    try:
        host = d.boards.connect(1)
        host.command("AX; LP500;")
        door = f"http://127.0.0.1:{d.port}"
        with _page_server(HOSTILE.replace("DOOR", door)) as port:
            browser.get(f"http://127.0.0.1:{port}/")
            body = browser.find_element(By.TAG_NAME, "body")
            _until(browser, lambda _d: body.get_attribute("data-done"), "the page never ran")
            out = json.loads(body.get_attribute("data-done"))  # (its fetches answered)
            c = d.client
            assert c.clock()[0]["paused"] is False
            assert c.board(1)["axes"][0]["switches"]["plus"]["fault"] is None
            _until(browser, lambda _d: d.door.refusals[415] + d.door.refusals[403] >= 7,
                   f"the door never saw the page's requests: {dict(d.door.refusals)}")
        # it could read nothing: a CORS read and the stream fail, an opaque read is empty
        assert out["read"] == "refused" and out["stream"] == "refused", out
        assert out["opaque"] == "read ", out
        assert out["json"] == "refused", out  # its preflight is not granted
        # and did nothing: the clock runs, no fault stuck, the board not reset
        assert c.clock()[0]["paused"] is False
        assert c.board(1)["axes"][0]["switches"]["plus"]["fault"] is None
        assert host.query("AX; RP") == "500"
        refused = dict(d.door.refusals)
        assert refused.get(403, 0) >= 5, refused  # Origin / Sec-Fetch-Site: every attempt
        assert set(refused) <= {403, 415}, refused
    finally:
        d.close()


def test_a_rebinding_name_for_loopback_gets_no_panel(browser) -> None:
    from selenium.webdriver.common.by import By

    d = Door(("MAXk-8000",))
    try:
        browser.get(f"http://{REBOUND}:{d.port}/api/boards/1/traffic")
        text = browser.find_element(By.TAG_NAME, "body").text
        assert "does not name it" in text and "hosts" not in text
        browser.get(f"http://{REBOUND}:{d.port}/")
        assert not browser.find_elements(By.ID, "boards")
        assert d.door.refusals[421] >= 2  # (and the browser's own favicon asks)
        browser.get(f"http://localhost:{d.port}/")  # the door's own names open it
        _until(browser, lambda b: b.find_elements(By.ID, "board-1"), "no panel on localhost")
    finally:
        d.close()


def _outside_address() -> str | None:
    """An address of this machine that is not loopback (None when it has none)."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:
        try:
            probe.connect(("192.0.2.1", 9))  # (no packet is sent: a route is chosen)
        except OSError:
            return None
        address = probe.getsockname()[0]
    return None if address.startswith("127.") else address


def test_the_panel_works_off_loopback_with_its_token(browser) -> None:
    """Listening on an outside address of this machine (or, lacking one, on every
    address, reached through 127.0.0.1): the page opened with its token loads its
    script and style, streams, and its buttons act; without the token nothing loads."""
    from selenium.webdriver.common.by import By

    outside = _outside_address()
    d = Door(("MAXk-8000", "PoKeys57CNC"), host=outside or "0.0.0.0")
    try:
        token = d.door.token
        assert token
        base = f"http://{outside or '127.0.0.1'}:{d.port}"
        browser.get(base + "/")
        assert "needs its token" in browser.find_element(By.TAG_NAME, "body").text
        browser.get(f"{base}/?token={token}")
        _until(browser, lambda b: b.find_elements(By.ID, "board-2"), "the panel never drew")
        body = browser.find_element(By.TAG_NAME, "body")
        _until(browser, lambda _d: int(body.get_attribute("data-updates") or 0) > 3,
               "the stream never came")
        shown = browser.execute_script(
            "return getComputedStyle(document.querySelector('header')).display")
        assert shown == "flex"  # the style sheet's rule applies: it loaded with the token
        browser.find_element(By.ID, "pause").click()
        _until(browser, lambda _d: d.client.clock()[0]["paused"], "pause never acted")
        browser.find_element(By.ID, "run").click()
        _until(browser, lambda _d: not d.client.clock()[0]["paused"], "run never acted")
        assert d.door.refusals[401] >= 1  # the page without its token
    finally:
        d.close()
