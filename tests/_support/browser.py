"""Helpers of the browser tests (tests/viewer): bounded waits, canvas pixels read in the page,
the page's debug state."""

from __future__ import annotations

import base64
import time
from collections.abc import Callable
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
