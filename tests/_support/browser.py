"""Helpers of the browser tests (tests/viewer): bounded waits, canvas pixels read in the page,
the page's debug state."""

from __future__ import annotations

import base64
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

import numpy as np

#: The 3D scene's clear colour 0x30303a as BGR.
BACKGROUND = np.array([58, 48, 48])


def wait_for(predicate: Callable[[], Any], timeout: float = 10.0, what: str = "") -> Any:
    """Poll ``predicate`` until it returns a true value (returned), else fail after
    ``timeout`` s naming ``what``."""
    end = time.monotonic() + timeout
    while True:
        value = predicate()
        if value:
            return value
        if time.monotonic() > end:
            raise AssertionError(f"timed out after {timeout} s waiting for {what}")
        time.sleep(0.05)


def canvas_pixels(page: Any, selector: str) -> np.ndarray:
    """The canvas content as a BGR array, from ``canvas.toDataURL()`` in the page."""
    import cv2

    url = page.evaluate(f"document.querySelector('{selector}').toDataURL('image/png')")
    assert url.startswith("data:image/png;base64,")
    data = np.frombuffer(base64.b64decode(url.split(",", 1)[1]), np.uint8)
    image = cv2.imdecode(data, cv2.IMREAD_COLOR)
    assert image is not None
    assert image.size
    return image


def drawn_fraction(image: np.ndarray) -> float:
    """Share of pixels that differ from the clear colour."""
    diff = np.abs(image.astype(int) - BACKGROUND).max(axis=2)
    return float((diff > 12).mean())


def debug(page: Any, key: str) -> Any:
    """``window.posekitViewer.<key>`` in the page (the page's introspection object)."""
    return page.evaluate(f"window.posekitViewer && window.posekitViewer.{key}")


def drag_tool(page: Any, tool: str, start: dict[str, float], end: dict[str, float]) -> None:
    """Switch a pose tool on (its button ``tool``, e.g. ``#goal-tool``) and press at ``start``,
    drag to ``end`` and release (client coordinates, as ``posekitViewer.project`` gives)."""
    page.click(tool)
    assert page.get_attribute(tool, "aria-pressed") == "true", f"{tool} did not switch on"
    page.mouse.move(start["x"], start["y"])
    page.mouse.down()
    page.mouse.move(end["x"], end["y"], steps=5)
    page.mouse.up()


# -- the page's displays (docs/viewer.md, "Writing a display")
def displays(page: Any) -> dict[str, Any]:
    """``window.posekitViewer.displays()``: every display, the subscriptions, counts."""
    state: dict[str, Any] = page.evaluate("window.posekitViewer.displays()")
    return state


def display_entry(page: Any, name: str, topic: str) -> dict[str, Any] | None:
    """The display ``name`` of ``topic`` (id, options, status, info), or None."""
    for d in displays(page)["displays"]:
        if d["display"] == name and d["topic"] == topic:
            return dict(d)
    return None


def display_info(page: Any, name: str, topic: str) -> Any:
    """The display's ``info()`` (None while it is not added or has drawn nothing)."""
    d = display_entry(page, name, topic)
    return d["info"] if d else None


def add_from_topic_list(page: Any, topic: str, name: str, timeout: float = 10.0
                        ) -> dict[str, Any]:
    """Click the topic list's **+ name** button of ``topic``; the new display's entry."""
    button = f"#topics tr[data-topic='{topic}'] button[data-add-display='{name}']"
    wait_for(lambda: page.query_selector(button), timeout,
             what=f"the '+ {name}' button of {topic}")
    page.click(button)
    return dict(wait_for(lambda: display_entry(page, name, topic), what=f"the {name} display"))


def set_option(page: Any, display_id: int, key: str, value: Any) -> None:
    """Change an option in the display's form, as a user does (input/change events)."""
    row = f"#display-list details[data-display-id='{display_id}']"
    page.evaluate(f"document.querySelector(\"{row}\").open = true")
    selector = f"{row} [data-option='{key}']"
    kind = page.eval_on_selector(selector, "e => e.tagName === 'SELECT' ? 'select' : e.type")
    if isinstance(value, bool):
        page.set_checked(selector, value)
    elif kind == "select":
        page.select_option(selector, value)
    elif kind == "color":  # a colour input takes its value and a change event
        page.eval_on_selector(selector, "(e, v) => { e.value = v; "
                              "e.dispatchEvent(new Event('change')); }", value)
    else:  # number and text fields: typed (input events)
        page.fill(selector, str(value))


def set_display_shown(page: Any, display_id: int, shown: bool) -> None:
    """Tick or untick the display's box in the Displays panel."""
    box = f"#display-list details[data-display-id='{display_id}'] .display-enabled"
    if shown:
        page.check(box)
    else:
        page.uncheck(box)


@contextmanager
def viewer_on(run: Any) -> Iterator[Any]:
    """A viewer attached in process to a started scenario ``run`` on a free port, the run's
    executor spinning in a thread; yields the server (``url``, ``tap``), then stops the
    server, shuts the run down and joins the thread (bounded)."""
    from posekit.cli.view_cmd import attach_to_run

    server = attach_to_run(run, port=0)
    spinner = threading.Thread(target=run.executor.spin, daemon=True)
    spinner.start()
    try:
        yield server
    finally:
        server.stop()
        run.shutdown()
        spinner.join(timeout=5.0)
