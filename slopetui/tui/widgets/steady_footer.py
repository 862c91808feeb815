"""Textual's footer, rebuilt only when the keys it shows change.

Textual's ``Footer`` rebuilds itself (removes and mounts a widget per key, styles each)
whenever its screen's bindings are updated, and a screen's bindings are updated every
time the screen comes back into view, though its keys are the same as before: with the
sweeps screen that rebuild was the largest part of switching back to it. This one
compares what it would show with what it shows, and rebuilds only on a difference.
"""

from __future__ import annotations

from typing import Any

from textual.screen import Screen
from textual.widgets import Footer


class SteadyFooter(Footer):
    """A ``Footer`` that skips rebuilding itself with the keys it already shows."""

    _shown: tuple[Any, ...] | None = None

    def bindings_changed(self, screen: Screen[Any]) -> None:
        shown = (self.compact, self.show_command_palette,
                 *((binding.key, binding.description, binding.action, binding.show,
                    binding.group, enabled, tooltip)
                   for _, binding, enabled, tooltip in screen.active_bindings.values()))
        if self._bindings_ready and shown == self._shown:
            return
        if screen.app.app_focus and self.is_attached and screen is self.screen:
            self._shown = shown  # what the rebuild below shows (Footer.bindings_changed)
        super().bindings_changed(screen)
