"""Help (? or F1): every key of the screen it was opened from, with what it does.

The list is generated, not written: it is the screen's active bindings
(``Screen.active_bindings``: the focused widget's, the screen's and the app's, as Textual
would dispatch a key at the moment help was asked for), the ones hidden from the footer
(``show=False``) included. So it cannot go stale when a screen gains or changes a key.
The longer text of a key is its binding's tooltip, else the first paragraph of its
action's docstring.

It is a modal: the app's keys other than the priority ones (ctrl+q, ctrl+p) do not reach
the screen below while it is open. Escape, q, ? or F1 close it; it scrolls at 80x24.
"""

from __future__ import annotations

import inspect
import re
from dataclasses import dataclass
from typing import Any

from rich.table import Table
from rich.text import Text
from textual.actions import ActionError, parse
from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import VerticalScroll
from textual.dom import DOMNode
from textual.screen import ModalScreen, Screen
from textual.widgets import Static

#: Characters of an action's docstring shown at most (the first paragraph, on one line).
DETAIL_CHARS = 160
#: The actions of the keys every Textual screen has (focus next, copy...).
TEXTUAL_SCREEN_ACTIONS = frozenset(b.action for b in Screen.BINDINGS if isinstance(b, Binding))
#: Words of a screen's class name written in capitals.
ACRONYMS = {"sql"}
#: [text](url) and [text][reference] in docstrings: shown as their text.
MARKDOWN_LINK = re.compile(r"\[([^\]]+)\](?:\([^)]*\)|\[[^\]]*\])")


@dataclass(frozen=True)
class HelpRow:
    keys: str          # as the footer shows them, several for one action: "? f1"
    description: str   # the footer's word for it
    detail: str        # the tooltip or the action's docstring; "" when there is none
    enabled: bool = True


@dataclass(frozen=True)
class HelpSection:
    title: str
    rows: tuple[HelpRow, ...]


def screen_name(screen: Screen[Any]) -> str:
    """SweepsScreen -> "Sweeps", RunDetailScreen -> "Run detail", SqlScreen -> "SQL"."""
    name = type(screen).__name__.removesuffix("Screen") or type(screen).__name__
    words = re.findall(r"[A-Z]+(?![a-z])|[A-Z]?[a-z0-9]+", name) or [name]
    words = [w.upper() if w.lower() in ACRONYMS else w for w in words]
    return " ".join([words[0], *(w if w.isupper() else w.lower() for w in words[1:])])


def action_doc(node: DOMNode, screen: Screen[Any], action: str) -> str:
    """The first paragraph of the docstring of the method an action string runs
    (``switch_mode('sql')``, ``app.quit``) on ``node``, on one line; "" if none."""
    try:
        destination, name, _ = parse(action)
    except ActionError:
        return ""
    target: object = {"app": screen.app, "screen": screen}.get(destination, node)
    method = getattr(target, f"action_{name}", None)
    doc = inspect.getdoc(method) if method is not None else None
    if not doc:
        return ""
    text = " ".join(doc.split("\n\n")[0].split())
    text = MARKDOWN_LINK.sub(r"\1", text).replace("`", "")  # Textual's docstrings link
    return text if len(text) <= DETAIL_CHARS else text[:DETAIL_CHARS - 1] + "…"


def section_title(node: DOMNode, screen: Screen[Any]) -> str:
    if node is screen.app:
        return "Everywhere"
    if node is screen:
        return f"This screen ({screen_name(screen)})"
    widget_id = f" #{node.id}" if node.id else ""
    return f"The focused {type(node).__name__}{widget_id}"


@dataclass
class _Keys:
    """The keys of one action of one node, gathered (one row)."""

    keys: list[str]
    tooltip: str
    enabled: bool


def help_sections(screen: Screen[Any]) -> list[HelpSection]:
    """The active bindings of ``screen`` now, by where they are defined: the screen, then
    the focused widget (and its containers), then the app. A key bound in several places
    is listed where it acts (Textual's precedence); keys of one action share a row."""
    app = screen.app
    found: dict[DOMNode, dict[tuple[str, str], _Keys]] = {}
    for node, binding, enabled, tooltip in screen.active_bindings.values():
        if binding.system:  # ctrl+c's "press ctrl+q to quit" reminder: not a command
            continue
        row = found.setdefault(node, {}).setdefault(
            (binding.action, binding.description or binding.action),
            _Keys([], tooltip or binding.tooltip, enabled))
        row.keys.append(app.get_key_display(binding))
    sections = []
    for node in sorted(found, key=lambda n: (n is app, n is not screen)):  # screen, widgets, app
        rows = list(found[node].items())
        if node is screen:  # its own keys before those every Textual screen has (tab, copy)
            rows.sort(key=lambda item: item[0][0] in TEXTUAL_SCREEN_ACTIONS)
        section = []
        for (action, description), keys in rows:
            detail = keys.tooltip or action_doc(node, screen, action)
            if detail.rstrip(".").lower() == description.lower():
                detail = ""
            section.append(HelpRow(" ".join(dict.fromkeys(keys.keys)), description, detail,
                                   keys.enabled))
        sections.append(HelpSection(section_title(node, screen), tuple(section)))
    return sections


def section_table(section: HelpSection) -> Table:
    table = Table(box=None, show_header=False, expand=True, padding=(0, 1, 0, 0))
    table.add_column("keys", no_wrap=True, width=11, style="bold")
    table.add_column("what", width=18)  # the same in every section: they line up
    table.add_column("detail", ratio=1, style="dim")
    for row in section.rows:
        what = Text(row.description) if row.enabled else Text(f"{row.description} (not now)",
                                                              style="dim")
        table.add_row(Text(row.keys), what, Text(row.detail))
    return table


class HelpScreen(ModalScreen[None]):
    """The keys of the screen below, as ``help_sections`` lists them."""

    BINDINGS = [
        Binding("escape,q,question_mark,f1", "dismiss", "Close", id="help.close"),
    ]

    def __init__(self, sections: list[HelpSection], title: str, palette_key: str) -> None:
        super().__init__()
        self.sections = sections
        self.title_text = title
        self.palette_key = palette_key

    @classmethod
    def of(cls, screen: Screen[Any]) -> HelpScreen:
        """The help of ``screen``, read before the help is pushed (focus is still there)."""
        app = screen.app
        palette = app.get_key_display(Binding(app.COMMAND_PALETTE_BINDING, "command_palette"))
        return cls(help_sections(screen), f"Keys: {screen_name(screen)}", palette)

    def compose(self) -> ComposeResult:
        with VerticalScroll(id="help-box") as box:
            box.border_title = self.title_text
            box.border_subtitle = "esc, q or ? closes"
            yield Static(Text(f"Every command is in the palette too ({self.palette_key}): "
                              "open run N, new sweep from a preset, export, go to a screen…"),
                         id="help-hint")
            for section in self.sections:
                yield Static(Text(section.title), classes="help-section")
                yield Static(section_table(section), classes="help-keys")

    def on_mount(self) -> None:
        self.query_one("#help-box").focus()  # arrows and page keys scroll it

    def rows(self) -> list[HelpRow]:
        """Every row, in the order shown."""
        return [row for section in self.sections for row in section.rows]
