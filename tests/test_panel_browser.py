"""The front panel in a real browser: headless Chromium from the distribution's packages,
driven by Selenium through the distribution's chromedriver (nothing downloaded). The page
is served by a real `maxk serve --control` (the maxk_served fixture), on the wall clock:
the waits below are liveness bounds, never measurements.

Locally these tests skip when the browser is not installed; in CI (CI set) they run,
and a missing browser is a failure (.ci/run installs it)."""

from __future__ import annotations

import io
import os
import socket
from collections.abc import Iterator
from pathlib import Path

import pytest

from maxk import testing
from tests.browsers import chromium, skip_without_browser

maxk_served = testing.maxk_served

WAIT = 20.0  # seconds a page may take to show something (a loaded CI machine)

skip_without_browser()


@pytest.fixture
def browser() -> Iterator[object]:
    with chromium() as driver:
        yield driver


def _until(driver: object, predicate, message: str):
    from selenium.webdriver.support.ui import WebDriverWait

    return WebDriverWait(driver, WAIT, poll_frequency=0.05).until(predicate, message)


def _max(sock: socket.socket, text: str) -> str:
    """A MAX reply line (notifications `%...` set aside, as the EPICS driver does)."""
    sock.sendall(text.encode())
    data = b""
    while True:
        while b"\n\r" not in data:
            chunk = sock.recv(4096)
            assert chunk, "the door hung up"
            data += chunk
        line, data = data.split(b"\n\r", 1)
        if not line.startswith(b"%"):
            return line.decode("latin-1")


def test_clicking_a_limit_lamp_trips_it_for_the_host(maxk_served, browser) -> None:
    from selenium.webdriver.common.by import By

    served = maxk_served("MAXk-8000")
    browser.get(served.url + "/")
    lamp = _until(browser, lambda d: d.find_element(By.ID, "lamp-1-X-plus"), "no X+ lamp")
    with socket.create_connection(served.doors[0].tcp, timeout=10) as host:
        assert _max(host, "AX; VL2000; MR1000000; GO; QA\n")[2] == "N"
        lamp.click()
        _until(browser, lambda d: "on" in lamp.get_attribute("class").split(),
               "the lamp never lit")
        qa = _max(host, "QA\n")
        assert qa[2] == "L", qa  # the host reads the limit the click tripped
        assert served.client.board(1)["axes"][0]["switches"]["plus"]["fault"] == "active"
        lamp.click()  # a second click clears it in the world
        _until(browser, lambda d: "on" not in lamp.get_attribute("class").split(),
               "the lamp never went out")
        assert served.client.board(1)["axes"][0]["switches"]["plus"]["fault"] is None


def test_a_position_moves_on_the_page_while_a_host_moves_the_axis(maxk_served,
                                                                   browser) -> None:
    from selenium.webdriver.common.by import By

    served = maxk_served("MAXk-8000", "PoKeys57CNC")
    browser.get(served.url + "/")
    cell = _until(browser, lambda d: d.find_element(By.CSS_SELECTOR, "#axis-1-Y .position"),
                  "no Y position")
    _until(browser, lambda d: cell.text == "0", "no position shown")
    with socket.create_connection(served.doors[0].tcp, timeout=10) as host:
        assert _max(host, "AY; VL4000; AC40000; MA8000; GO; RP\n") == "0"
        seen: set[int] = set()

        def moving(_d: object) -> bool:
            seen.add(int(cell.text))
            return len([p for p in seen if 0 < p < 8000]) >= 3

        _until(browser, moving, "the position never moved on the page")
        _until(browser, lambda d: cell.text == "8000", "the move's end never shown")
    assert browser.find_element(By.ID, "board-2")  # every board has its card
    updates = int(browser.find_element(By.TAG_NAME, "body").get_attribute("data-updates"))
    assert updates > 3


def test_the_page_is_drawn_not_blank(maxk_served, browser, tmp_path: Path) -> None:
    from PIL import Image
    from selenium.webdriver.common.by import By

    served = maxk_served("MAXk-8000", "MM4005", "MC405", "PoKeys57CNC")
    browser.get(served.url + "/")
    _until(browser, lambda d: len(d.find_elements(By.CSS_SELECTOR, "section.board")) == 4,
           "four boards never drawn")
    with socket.create_connection(served.doors[0].tcp, timeout=10) as host:
        _max(host, "AX; VL4000; MR2000; GO; RP\n")
        _until(browser, lambda d: d.find_element(By.CSS_SELECTOR, "#axis-1-X .position").text
               == "2000", "the move never shown")
    path = tmp_path / "panel.png"
    assert browser.save_screenshot(str(path))
    Path(os.environ.get("MAXK_PANEL_SHOT", tmp_path / "kept.png")).write_bytes(path.read_bytes())
    image = Image.open(io.BytesIO(path.read_bytes())).convert("RGB")
    assert image.size[0] >= 1000 and image.size[1] >= 700
    colours = image.getcolors(maxcolors=1 << 20) or []
    assert len(colours) > 50  # text, lamps, charts: not one flat colour
    biggest = max(count for count, _ in colours)
    assert biggest < 0.9 * image.size[0] * image.size[1]
    text = browser.find_element(By.ID, "board-2").text
    assert "MM4005" in text and "XY path" in text
    assert "PWM mark" in browser.find_element(By.ID, "board-3").text
    assert "slot buffer 0/128" in browser.find_element(By.ID, "board-4").text


def test_an_input_click_sets_the_world_input(maxk_served, browser) -> None:
    from selenium.webdriver.common.by import By

    served = maxk_served("MAXk-8000")
    browser.get(served.url + "/")
    bit = _until(browser, lambda d: d.find_element(By.ID, "in-1-3"), "no input 3")
    bit.click()
    _until(browser, lambda d: "on" in bit.get_attribute("class").split(), "input never lit")
    assert served.client.board(1)["inputs"]["3"] is True
    with socket.create_connection(served.doors[0].tcp, timeout=10) as host:
        assert int(_max(host, "BX\n"), 16) & 0x8  # the host reads input 3 high


def _type(browser: object, board: int, line: str) -> None:
    """A line typed in the board's console and Enter; waits for its answer."""
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.keys import Keys

    box = browser.find_element(By.ID, f"console-{board}")  # type: ignore[attr-defined]
    before = int(box.get_attribute("data-lines") or 0)
    field = browser.find_element(By.ID, f"console-in-{board}")  # type: ignore[attr-defined]
    field.send_keys(line, Keys.ENTER)
    _until(browser, lambda d: int(box.get_attribute("data-lines") or 0) > before,
           f"no answer to {line!r}")


def _console_lines(browser: object, board: int) -> list[tuple[str, str]]:
    from selenium.webdriver.common.by import By

    out = browser.find_element(By.ID, f"console-out-{board}")  # type: ignore[attr-defined]
    return [(e.get_attribute("class"), e.text) for e in out.find_elements(By.TAG_NAME, "div")]


def test_the_console_types_the_controllers_language(maxk_served, browser) -> None:
    """A MAXk board's console: the move typed runs (X reaches 1000 on the page), AX RP
    answers 1000, Tab completes VL with its summary, a refused command is marked; the
    same console on an MM4005 and an MC405 in their own languages."""
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.keys import Keys

    served = maxk_served("MAXk-8000", "MM4005", "MC405")
    browser.get(served.url + "/")
    _until(browser, lambda d: d.find_element(By.ID, "console-in-1"), "no console")
    _type(browser, 1, "AX; VL5000; AC50000; MR1000; GO;")
    cell = browser.find_element(By.CSS_SELECTOR, "#axis-1-X .position")
    _until(browser, lambda d: cell.text == "1000", "X never reached 1000 on the page")
    _type(browser, 1, "AX RP")
    assert _console_lines(browser, 1)[-1] == ("console-reply", "1000")
    field = browser.find_element(By.ID, "console-in-1")
    field.send_keys("AX; V")
    field.send_keys(Keys.TAB)
    hint = browser.find_element(By.ID, "console-hint-1")
    _until(browser, lambda d: "VL" in hint.text, "Tab offered no VL")
    summary = served.client.console_words(1, "VL")[0]["summary"]
    assert f"VL  {summary}" in hint.text.splitlines()
    field.send_keys("L")
    field.send_keys(Keys.TAB)
    _until(browser, lambda d: field.get_attribute("value") == "AX; VL", "VL not completed")
    field.clear()
    _type(browser, 1, "MR")
    assert _console_lines(browser, 1)[-1] == (
        "console-err", "! command error: 'MR': MR needs an operand")
    field.send_keys(Keys.ARROW_UP)  # the history
    assert field.get_attribute("value") == "MR"
    field.clear()
    _type(browser, 2, "1PA5")
    _until(browser, lambda d: d.find_element(By.CSS_SELECTOR, "#axis-2-1 .position").text
           not in ("", "0", "0.0000"), "the MM4005's axis never moved on the page")
    _type(browser, 2, "1PA99999999")
    assert _console_lines(browser, 2)[-1] == ("console-err", "! C Parameter out of limits")
    _type(browser, 3, "?1+1")
    assert _console_lines(browser, 3)[-1] == ("console-reply", "2")
    _type(browser, 3, "MOVEE(10)")
    assert _console_lines(browser, 3)[-1] == ("console-err", "! Variable not defined")
    traffic = [h for h in served.client.traffic(1) if h["transport"] == "console"]
    assert traffic and traffic[0]["entries"][0]["text"] == "AX; VL5000; AC50000; MR1000; GO;\r"


def test_the_console_works_off_loopback_with_the_token(browser) -> None:
    """Off loopback every request needs the token: the console's lines, its completions
    and its saved script carry the one the page was opened with."""
    import urllib.request

    from selenium.webdriver.common.by import By

    from tests.test_control_browser_security import Door, _outside_address

    outside = _outside_address()
    d = Door(("MAXk-8000",), host=outside or "0.0.0.0")
    try:
        base = f"http://{outside or '127.0.0.1'}:{d.port}"
        browser.get(f"{base}/?token={d.door.token}")
        _until(browser, lambda b: b.find_elements(By.ID, "console-in-1"), "no console")
        _type(browser, 1, "AX RP")
        assert _console_lines(browser, 1)[-1] == ("console-reply", "0")
        link = browser.find_element(By.ID, "console-save-1").get_attribute("href")
        assert f"token={d.door.token}" in link
        with urllib.request.urlopen(link, timeout=10) as answer:
            assert answer.read().decode().endswith("AX RP\n< 0\n")
    finally:
        d.close()
