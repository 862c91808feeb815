"""The command palette's commands (ctrl+p): every action of the application by name.

A key reaches one screen's actions; the palette reaches them all from anywhere, and takes
what a key cannot: an id ("run 12", "pause sweep 3", "export sweep 3 json"). The list is
built when the palette asks for it, from the state of the app and of the screen the
palette was opened from (the sweep selected there, whether it draws a figure, whether the
store failed to open), so it offers only what can be done now. Textual's own system
commands (theme, keys, screenshot...) stay in the palette beside these.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from functools import partial
from typing import TYPE_CHECKING, Any, cast

from textual.binding import Binding
from textual.command import DiscoveryHit, Hit, Hits, Provider
from textual.markup import escape
from textual.screen import Screen

from slopetui.sql_files import FILE_FORMATS
from slopetui.sweeps.export_files import FORMATS
from slopetui.sweeps.presets import PRESETS
from slopetui.tui.screens.confirm import ask_then_control_id
from slopetui.tui.screens.spec_compare import compare_sweeps
from slopetui.tui.screens.sql import SqlScreen
from slopetui.tui.screens.sweep_labels import edit_labels
from slopetui.tui.screens.sweeps import SweepsScreen

if TYPE_CHECKING:
    from slopetui.tui.app import SlopeApp

#: How the palette names the modes (SlopeApp.MODES); a mode missing here is named by its key.
SCREEN_NAMES = {"sweeps": "Sweeps", "queue": "Queue and workers", "sql": "SQL console",
                "branches": "Branches (continuations)"}

#: Controls of a sweep, as the palette and ``slopetui pause|resume|cancel`` name them.
CONTROLS = ("pause", "resume", "cancel", "delete")

#: The analyses' forms (SlopeApp.open_analysis): kind, what the palette calls it, and
#: where it opens and what it does.
ANALYSES = (
    ("continuation", "continuation of periodic orbits",
     "at the diagram cursor's or a run's point; queued for the pool (slopetui continue; "
     "Branches screen key c)"),
    ("hysteresis", "hysteresis sweep",
     "up and down one parameter around the cursor's or a run's point; queued for the pool "
     "(slopetui hysteresis; Branches screen key h)"),
    ("orbit", "periodic orbit at the cursor's point",
     "its period, amplitude and Floquet multipliers, computed here (slopetui orbit; key o "
     "in a run's detail)"),
)

RERUN = re.compile(r"(?:certified\s+)?re-?run\s+(?:run\s+)?#?(\d+)", re.IGNORECASE)
OPEN_RUN = re.compile(r"(?:open\s+)?run\s+#?(\d+)", re.IGNORECASE)
CONTROL_SWEEP = re.compile(rf"({'|'.join(CONTROLS)})\s+sweep\s+#?(\d+)", re.IGNORECASE)
COMPARE_SWEEPS = re.compile(r"compare\s+sweeps?\s+#?(\d+)\s*(?:,|and|with|to)?\s*#?(\d+)",
                            re.IGNORECASE)
EXPORT_SWEEP = re.compile(rf"export\s+sweep\s+#?(\d+)(?:\s+(?:as\s+)?({'|'.join(FORMATS)}))?",
                          re.IGNORECASE)

#: The score of a command the query names exactly ("run 12"): above any fuzzy match,
#: whose scores (textual.fuzzy) grow with the letters matched and may pass 1.
TYPED_SCORE = 1e6


@dataclass(frozen=True)
class Command:
    name: str
    help: str
    run: Callable[[], Any]


def selected_sweep(app: SlopeApp) -> int | None:
    """The sweep selected on the sweeps screen, if it is in the current mode's stack (a
    run's detail may be open over it)."""
    for screen in reversed(app.screen_stack):
        if isinstance(screen, SweepsScreen):
            return screen.selected
    return None


def shown_run(screen: Screen[Any]) -> int | None:
    """The run whose detail ``screen`` is, if it is one (duck-typed: the run detail's
    module loads numba, kept out of the palette's imports)."""
    run_id = getattr(screen, "run_id", None)
    return run_id if isinstance(run_id, int) and hasattr(screen, "action_rerun") else None


def key_of(app: SlopeApp, action: str) -> str:
    """" (key k)" for the app's binding of ``action``, "" if it has none."""
    for binding in type(app).BINDINGS:
        if isinstance(binding, Binding) and binding.action == action:
            first = binding.with_key(binding.key.split(",")[0])
            return f" (key {app.get_key_display(first)})"
    return ""


def commands(app: SlopeApp, screen: Screen[Any]) -> list[Command]:
    """What the palette offers, for ``screen`` (the one it was opened from)."""
    folder = app.figure_folder
    found = [Command("Help: the keys of this screen", "every key of the screen, hidden ones too"
                     + key_of(app, "help"), partial(app.show_help, screen))]
    if app.store_error is not None:
        found += [Command("Retry opening the store", f"it failed: {app.store_error}",
                          app.retry_store),
                  Command("Open another store", "a database URL or a file path",
                          app.action_store_dialog)]
    found.append(Command("New sweep", "the form, empty" + key_of(app, "new_sweep"),
                         app.new_sweep))
    found += [Command(f"New sweep: {p.figure}, {p.title}",
                      f"preset {p.key}: the form filled with the paper's panel, to change "
                      "before submitting", partial(app.new_sweep, p.key))
              for p in PRESETS]
    found += [Command(f"New {title}", f"the form, {help}", partial(app.open_analysis, kind))
              for kind, title, help in ANALYSES]
    run = shown_run(screen)
    if run is not None:
        found.append(Command(f"Certified re-run of run {run} (shown)",
                             "queue it again with stop = certified, a one-run sweep (key u)",
                             partial(app.certified_rerun, run)))
    found.append(Command("Certified re-run of a run by id",
                         "type rerun run and its id, e.g. rerun run 12",
                         partial(app.notify, "type rerun run and the run's id in the palette, "
                                             "e.g. rerun run 12")))
    for mode in app.MODES:
        found.append(Command(f"Go to {SCREEN_NAMES.get(mode, mode)}", "screen"
                             + key_of(app, f"switch_mode('{mode}')"),
                             partial(app.switch_mode, mode)))
    found.append(Command("Open a run by id", "type run and its id, e.g. run 12",
                         partial(app.notify, "type run and the run's id in the palette, "
                                             "e.g. run 12")))
    marked = ", ".join(map(str, app.marked)) or "none"
    found.append(Command("Compare the marked runs", f"marked: {marked}" + key_of(app, "compare"),
                         app.action_compare))
    if app.marked:
        found.append(Command("Clear the marked runs", f"marked: {marked}; the store keeps marks "
                             "across restarts until cleared", app.clear_marks))
    if isinstance(screen, SqlScreen) and screen.results is not None:
        found += [Command(f"Save the console's results as {fmt.upper()}",
                          f"the rows shown, into {folder}" + (" (ctrl+s)" if fmt == "csv" else ""),
                          partial(screen.action_save_results, fmt))
                  for fmt in FILE_FORMATS]
    figure = getattr(screen, "action_figure", None)
    if callable(figure):
        found.append(Command("Write this screen's figure", f"into {folder}", figure))
    sweep = selected_sweep(app)
    if sweep is not None:
        found += [Command(f"{action.capitalize()} sweep {sweep} (selected)",
                          f"or type {action} sweep and an id",
                          partial(ask_then_control_id, app, action, sweep))
                  for action in CONTROLS]
        found.append(Command(f"Compare the spec of sweep {sweep} (selected) with another",
                             f"type compare sweeps {sweep} and an id, e.g. compare sweeps "
                             f"{sweep} {max(sweep - 1, 1)}",
                             partial(app.notify, f"type compare sweeps {sweep} and the other "
                                                 "sweep's id in the palette")))
        found.append(Command(f"Rename, tag or annotate sweep {sweep} (selected)",
                             "its name, tags and note (key e; slopetui rename, tag, note)",
                             partial(edit_labels, app, sweep)))
        found += [Command(f"Export sweep {sweep} (selected) as {fmt.upper()}",
                          f"its runs, as slopetui export --{fmt}, into {folder}",
                          partial(app.export_sweep, sweep, fmt))
                  for fmt in FORMATS]
    found.append(Command("Quit slopetui", "ctrl+q anywhere, q where no text field has focus; "
                                          "the worker pool keeps running", app.exit))
    return found


def typed_commands(app: SlopeApp, query: str) -> Iterator[Command]:
    """The commands a query names with an id: "run 12", "open run 12", "pause sweep 3",
    "export sweep 3 csv", "compare sweeps 3 5"."""
    query = query.strip()
    if match := RERUN.fullmatch(query):
        run_id = int(match[1])
        yield Command(f"Certified re-run of run {run_id}",
                      "queue it again with stop = certified, a one-run sweep",
                      partial(app.certified_rerun, run_id))
    if match := OPEN_RUN.fullmatch(query):
        run_id = int(match[1])
        yield Command(f"Open run {run_id}", "its detail: time series, phase plane, spectrum",
                      partial(app.open_run, run_id))
    if match := CONTROL_SWEEP.fullmatch(query):
        action, sweep = match[1].lower(), int(match[2])
        yield Command(f"{action.capitalize()} sweep {sweep}", f"as slopetui {action} {sweep}",
                      partial(ask_then_control_id, app, action, sweep))
    if match := COMPARE_SWEEPS.fullmatch(query):
        a, b = int(match[1]), int(match[2])
        yield Command(f"Compare the specs of sweeps {a} and {b}",
                      f"side by side, the settings that differ marked (slopetui compare {a} {b})",
                      partial(compare_sweeps, app, a, b))
    if match := EXPORT_SWEEP.fullmatch(query):
        sweep = int(match[1])
        for fmt in [match[2].lower()] if match[2] else FORMATS:
            yield Command(f"Export sweep {sweep} as {fmt.upper()}",
                          f"its runs into {app.figure_folder}", partial(app.export_sweep, sweep, fmt))


class SlopeCommands(Provider):
    """slopetui's commands for Textual's command palette (SlopeApp.COMMANDS)."""

    @property
    def slope_app(self) -> SlopeApp:
        """``app``, typed: the provider is registered on SlopeApp only (its COMMANDS)."""
        return cast("SlopeApp", self.app)

    # The palette reads a str prompt and the help as markup: escaped, since paths, causes
    # and names may hold brackets.

    async def discover(self) -> Hits:
        for command in commands(self.slope_app, self.screen):
            yield DiscoveryHit(escape(command.name), command.run, text=command.name,
                               help=escape(command.help))

    async def search(self, query: str) -> Hits:
        for command in typed_commands(self.slope_app, query):
            yield Hit(TYPED_SCORE, escape(command.name), command.run, text=command.name,
                      help=escape(command.help))
        matcher = self.matcher(query)
        for command in commands(self.slope_app, self.screen):
            if (score := matcher.match(command.name)) > 0:
                yield Hit(score, matcher.highlight(command.name), command.run,
                          text=command.name, help=escape(command.help))
