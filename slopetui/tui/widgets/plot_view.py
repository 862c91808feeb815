"""A widget that shows a plotext rendering and redraws it at its own size."""

from __future__ import annotations

from collections.abc import Callable

from rich.text import Text
from textual.widgets import Static

#: Draws a plot of ``width`` x ``height`` cells, ANSI-coloured when ``color`` is true.
Renderer = Callable[[int, int, bool], str]


class PlotView(Static):
    """Renders ``renderer(width, height, color)`` on mount, on resize, and on ``redraw``.

    The renderers are pure functions of numbers (``slopetui.plots``), cheap compared to a
    run, so they are called on the UI thread; the data behind them is loaded in workers.
    """

    DEFAULT_CSS = """
    PlotView { width: 1fr; height: 1fr; min-height: 12; }
    """

    def __init__(self, renderer: Renderer | None = None, *, id: str | None = None,
                 classes: str | None = None) -> None:
        super().__init__("", id=id, classes=classes)
        self.renderer = renderer

    def on_mount(self) -> None:
        self.redraw()

    def on_resize(self) -> None:
        self.redraw()

    def show(self, renderer: Renderer | None) -> None:
        self.renderer = renderer
        self.redraw()

    def redraw(self) -> None:
        width, height = self.content_size.width, self.content_size.height
        if self.renderer is None or width < 30 or height < 12:
            self.update("" if self.renderer is None else "(too small to draw: enlarge the window)")
            return
        color = not self.app.no_color
        try:
            text = self.renderer(width, height, color)
        except ValueError as exc:  # e.g. nothing plottable yet
            self.update(str(exc))
            return
        self.update(Text.from_ansi(text) if color else Text(text))
