"""A preview page drawn in headless Chromium: its canvas, its figures and what it asked the network for.

:class:`Browser` starts Debian's ``chromium`` through its ``chromedriver`` (selenium, from the
``test`` extras; ``scripts/setup.sh test`` installs all three), with WebGL 2 on SwiftShader, the
software renderer Chromium ships (so the same page draws the same on any machine, GPU or none), or
with WebGL turned off. :meth:`Browser.show` loads a page at a URL fragment and waits for the
title the page sets when it has drawn (``morphkit: ready``) or given up (``morphkit: no WebGL``,
``morphkit: error``); :class:`Shot` holds what it drew. Selenium Manager is never asked to fetch
a browser: the binaries are found on ``PATH`` or refused with the command that installs them.
"""

from __future__ import annotations

import base64
import json
import os
import shutil
import time
from dataclasses import dataclass, field
from pathlib import Path
from types import TracebackType
from typing import Any

import cv2
import numpy as np

from ..errors import RenderError, ValidationError, expected_got

__all__ = ["Browser", "Shot", "browser_available", "READY", "DONE_TITLES"]

#: The title a page sets once it has drawn.
READY = "morphkit: ready"
#: Every title a page ends in.
DONE_TITLES = (READY, "morphkit: no WebGL", "morphkit: error")

_CHROMIUM = ("chromium", "chromium-browser", "google-chrome")


def _binaries() -> tuple[str | None, str | None]:
    chrome = next((p for p in (shutil.which(n) for n in _CHROMIUM) if p), None)
    return chrome, shutil.which("chromedriver")


def browser_available() -> str | None:
    """None when the browser test can run here, else why not (one line).

    Returns
    -------
    str or None
    """
    chrome, driver = _binaries()
    try:
        import selenium  # noqa: F401
    except ImportError:
        return "selenium is not installed (bash scripts/setup.sh test installs it)"
    if chrome is None or driver is None:
        return "chromium and chromedriver are not on PATH (bash scripts/setup.sh test installs them)"
    return None


@dataclass(frozen=True)
class Shot:
    """What a page drew.

    Parameters
    ----------
    title : str
        The page's last title.
    image : (h, w, 3) float32 or None
        The canvas, RGB in ``[0, 1]`` (None without WebGL).
    stats : dict
        The page's ``window.morphkitStats`` (frame time, image size, instances...).
    seconds : float
        From loading the page to its title.
    message : str
        The page's message box (e.g. "This page needs WebGL 2 ..."), "" when none is shown.
    errors : list of str
        The browser console's errors.
    """

    title: str
    image: np.ndarray | None
    stats: dict[str, Any]
    seconds: float
    message: str
    errors: list[str] = field(default_factory=list)


class Browser:
    """Headless Chromium driven by selenium (module docstring). Use as a context manager.

    Parameters
    ----------
    webgl : bool, optional
        False: start it with WebGL turned off (the page's "no WebGL" case).
    window : (width, height), optional
        The window, pixels.
    timeout_s : float, optional
        How long :meth:`show` waits for a page's title.

    Raises
    ------
    RenderError
        No selenium, chromium or chromedriver here (:func:`browser_available` says which), or the
        browser did not start.
    """

    def __init__(self, *, webgl: bool = True, window: tuple[int, int] = (1024, 768),
                 timeout_s: float = 60.0) -> None:
        why = browser_available()
        if why is not None:
            raise RenderError(expected_got("a browser", "headless chromium with chromedriver and selenium",
                                           why))
        from selenium import webdriver
        from selenium.webdriver.chrome.options import Options
        from selenium.webdriver.chrome.service import Service

        chrome, driver = _binaries()
        opts = Options()
        opts.binary_location = str(chrome)
        for a in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--hide-scrollbars",
                  f"--window-size={int(window[0])},{int(window[1])}", "--force-device-scale-factor=1",
                  "--autoplay-policy=no-user-gesture-required", "--mute-audio"):
            opts.add_argument(a)
        if webgl:
            opts.add_argument("--use-angle=swiftshader")
            opts.add_argument("--enable-unsafe-swiftshader")
        else:
            opts.add_argument("--disable-webgl")
            opts.add_argument("--disable-3d-apis")
        opts.set_capability("goog:loggingPrefs", {"browser": "ALL", "performance": "ALL"})
        self.timeout_s = float(timeout_s)
        try:
            self._d = webdriver.Chrome(options=opts, service=Service(executable_path=str(driver)))
        except Exception as exc:  # selenium's own errors: one line naming the browser
            raise RenderError(f"headless chromium did not start: {str(exc).splitlines()[0]}") from exc

    def __enter__(self) -> Browser:
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        self.close()

    def close(self) -> None:
        """Quit the browser."""
        d, self._d = getattr(self, "_d", None), None
        if d is not None:
            d.quit()

    def _wait(self, done: Any) -> float:
        t0 = time.perf_counter()
        while time.perf_counter() - t0 < self.timeout_s:
            if done():
                return time.perf_counter() - t0
            time.sleep(0.02)
        raise RenderError(expected_got("the page", f"drawn within {self.timeout_s:.0f} s",
                                       f"the title {self._d.title!r}"))

    def show(self, page: str | os.PathLike[str], fragment: str = "") -> Shot:
        """Load ``page`` at ``#fragment`` and wait for its title (module docstring).

        Parameters
        ----------
        page : path-like
            An HTML file.
        fragment : str, optional
            The URL fragment (without ``#``).

        Returns
        -------
        Shot
        """
        p = Path(page).resolve()
        if not p.is_file():
            raise ValidationError(expected_got("page", "an HTML file", repr(str(p))))
        self._d.get("about:blank")
        self._d.get_log("browser")
        self._d.get_log("performance")
        url = p.as_uri() + (f"#{fragment}" if fragment else "")
        t0 = time.perf_counter()
        self._d.get(url)
        self._wait(lambda: self._d.title in DONE_TITLES)
        seconds = time.perf_counter() - t0
        return self._shot(seconds)

    def redraw(self, fragment: str) -> Shot:
        """Set the open page's URL fragment and wait for it to draw again.

        Parameters
        ----------
        fragment : str
            Without ``#``.

        Returns
        -------
        Shot
        """
        return self.trigger("location.hash = arguments[0];", fragment)

    def trigger(self, script: str, *args: object) -> Shot:
        """Run ``script`` in the open page (e.g. move a slider) and wait for the page to draw again.

        Parameters
        ----------
        script : str
            JavaScript that makes the page redraw.
        *args
            Its ``arguments``.

        Returns
        -------
        Shot
        """
        self._d.execute_script("window.morphkitStats = null;")
        self._d.execute_script(script, *args)
        t = self._wait(lambda: self._d.execute_script("return window.morphkitStats") is not None)
        return self._shot(t)

    def _shot(self, seconds: float) -> Shot:
        d = self._d
        stats = d.execute_script("return window.morphkitStats || {}") or {}
        message = d.execute_script(
            "const m = document.getElementById('message'); "
            "return m && m.style.display !== 'none' ? m.textContent : '';") or ""
        image = None
        if d.title == READY:
            url = d.execute_script("return document.getElementById('view').toDataURL('image/png')")
            png = np.frombuffer(base64.b64decode(url.split(",", 1)[1]), np.uint8)
            rgb = cv2.cvtColor(cv2.imdecode(png, cv2.IMREAD_COLOR), cv2.COLOR_BGR2RGB)
            image = rgb.astype(np.float32) / np.float32(255.0)
        errors = [e["message"] for e in d.get_log("browser") if e.get("level") == "SEVERE"]
        return Shot(d.title, image, dict(stats), float(seconds), str(message), errors)

    def requests(self) -> list[str]:
        """The URLs the browser asked for since the last :meth:`show` (from its network log).

        Returns
        -------
        list of str
        """
        urls = []
        for e in self._d.get_log("performance"):
            msg = json.loads(e["message"])["message"]
            if msg.get("method") == "Network.requestWillBeSent":
                urls.append(msg["params"]["request"]["url"])
        return urls

    def run_script(self, script: str, *args: Any) -> Any:
        """Run JavaScript in the open page (``return`` gives a value back).

        Parameters
        ----------
        script : str
            The script.
        *args
            Its ``arguments``.

        Returns
        -------
        Any
        """
        return self._d.execute_script(script, *args)

    def load(self, page: str | os.PathLike[str]) -> None:
        """Load a page without waiting for a morphkit title (any HTML file).

        Parameters
        ----------
        page : path-like
            An HTML file.
        """
        self._d.get(Path(page).resolve().as_uri())
