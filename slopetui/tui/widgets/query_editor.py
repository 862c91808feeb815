"""The SQL console's editor: a code editor that says, while it has the keys, that it has
them and how to leave it.

Typed keys go into the query (the digits and q too, which elsewhere switch screens and
quit): a user who pressed 1 to go to the sweeps found a "1" in the query. So the editor
shows whose the keys are, in its border (brighter, and its subtitle) and in the footer,
whose entry for escape is this editor's "esc/tab Leave editor" while it has the focus
(the screen's "esc Editor" comes back once it has left); escape and tab move the focus
on to the results.
"""

from __future__ import annotations

from textual.binding import Binding
from textual.widgets import TextArea

#: The border's subtitle while the editor has the keys, and while it has not.
TYPING = "typing here · esc or tab leaves"
RESTING = "esc returns here"


class QueryEditor(TextArea):
    """A TextArea that leaves on escape (tab leaves it too: ``tab_behavior="focus"``)."""

    DEFAULT_CSS = """
    QueryEditor { border-subtitle-color: $text-muted; }
    QueryEditor:focus { border: tall $accent; border-subtitle-color: $accent; }
    """

    BINDINGS = [
        Binding("escape", "app.focus_next", "Leave editor", key_display="esc/tab",
                id="sql.leave_editor",
                tooltip="Leave the editor (tab too): the digits and q switch screens and "
                        "quit again"),
    ]

    def on_mount(self) -> None:
        self.border_subtitle = TYPING if self.has_focus else RESTING

    def on_focus(self) -> None:
        self.border_subtitle = TYPING

    def on_blur(self) -> None:
        self.border_subtitle = RESTING
