"""A small text progress bar for long runs (no dependencies).

The library reports progress through a callback ``progress(fraction, t)``; the CLI
draws it with :class:`ProgressBar`::

    bar = ProgressBar(sys.stderr)
    res = rfesim.simulate(sc, progress=bar)
    bar.close()

The bar shows the fraction done, the simulated time, the wall time and an estimate of
the time left. It redraws at most ``max_rate`` times per second, and only once the run
has lasted ``delay`` seconds (so quick runs print nothing).
"""
from __future__ import annotations

import sys
import time
from typing import TextIO


def format_duration(seconds: float) -> str:
    """``12.3 s``, ``4 min 05 s``, ``2 h 03 min``."""
    if seconds != seconds or seconds < 0:  # NaN or negative: unknown
        return "?"
    if seconds < 60.0:
        return f"{seconds:.1f} s"
    minutes, sec = divmod(int(round(seconds)), 60)
    if minutes < 60:
        return f"{minutes} min {sec:02d} s"
    hours, minutes = divmod(minutes, 60)
    return f"{hours} h {minutes:02d} min"


class ProgressBar:
    """A throttled one-line progress bar written to ``stream`` (stderr by default).

    Parameters
    ----------
    stream: where to draw; the line is redrawn in place with a carriage return.
    width: number of characters of the bar itself.
    max_rate: largest number of redraws per second.
    delay: seconds of wall time before the first draw (0: draw at once).
    enabled: False turns the bar into a no-op (the callback still works).
    clock: a ``time.perf_counter``-like function (for tests).
    """

    def __init__(self, stream: TextIO | None = None, *, width: int = 30, max_rate: float = 10.0,
                 delay: float = 0.0, enabled: bool = True, clock=time.perf_counter):
        self.stream = stream if stream is not None else sys.stderr
        self.width = int(width)
        self.min_interval = 1.0 / max_rate if max_rate > 0 else 0.0
        self.delay = float(delay)
        self.enabled = enabled
        self._clock = clock
        self._start = clock()
        self._last_draw = -float("inf")
        self._drawn = False
        self._drawn_complete = False  # 100 % drawn: nothing more to show
        self._last_len = 0
        self.fraction = 0.0
        self.time = 0.0
        self._first = None    # (wall clock, fraction) at the first update: the ETA ignores the start-up
        self.updates = 0      # number of callback calls
        self.draws = 0        # number of redraws

    # the library's callback signature
    def __call__(self, fraction: float, t: float) -> None:
        self.update(fraction, t)

    @property
    def elapsed(self) -> float:
        """Wall time since the bar was created (s)."""
        return self._clock() - self._start

    def eta(self) -> float:
        """Estimated wall time left (s) from the rate since the first update; NaN until known."""
        if self._first is None:
            return float("nan")
        wall0, frac0 = self._first
        done = self.fraction - frac0
        if done <= 0.0:
            return float("nan")
        return max(0.0, (self._clock() - wall0) * (1.0 - self.fraction) / done)

    def render(self) -> str:
        """The bar as text, e.g. ``[#######-------]  45.0%  t = 27 s  wall 3.1 s  ETA 3.8 s``."""
        frac = min(max(self.fraction, 0.0), 1.0)
        filled = int(round(frac * self.width))
        bar = "#" * filled + "-" * (self.width - filled)
        return (f"[{bar}] {100.0 * frac:5.1f}%  t = {self.time:.4g} s  wall {format_duration(self.elapsed)}"
                f"  ETA {format_duration(self.eta())}")

    def update(self, fraction: float, t: float) -> None:
        self.updates += 1
        self.fraction = float(fraction)
        self.time = float(t)
        if self._first is None:
            self._first = (self._clock(), self.fraction)
        if not self.enabled:
            return
        now = self._clock()
        if now - self._start < self.delay:
            return
        if self._drawn_complete or (now - self._last_draw < self.min_interval and fraction < 1.0):
            return
        self._draw()
        self._last_draw = now

    def _draw(self) -> None:
        text = self.render()
        pad = " " * max(0, self._last_len - len(text))
        try:
            self.stream.write("\r" + text + pad)
            self.stream.flush()
        except (OSError, ValueError):  # closed stream: stop drawing, never stop the run
            self.enabled = False
            return
        self._last_len = len(text)
        self._drawn = True
        self._drawn_complete = self.fraction >= 1.0
        self.draws += 1

    def close(self) -> None:
        """End the line if anything was drawn (call once the run is over)."""
        if self._drawn and self.enabled:
            try:
                self.stream.write("\n")
                self.stream.flush()
            except (OSError, ValueError):
                pass
        self._drawn = False

    def __enter__(self) -> "ProgressBar":
        return self

    def __exit__(self, *exc) -> None:
        self.close()
