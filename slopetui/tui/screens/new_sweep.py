"""New sweep: a form with inline validation, friction warnings, presets and an estimate.

The form is a view of a spec mapping (``slopetui.sweeps.spec``): every change re-parses
it, so the form and ``slopetui submit`` accept and refuse exactly the same sweeps.
"adaptive levels" (beside the name, so the form still fits 80x24) makes a phase
diagram adaptive (``[adaptive] levels``); empty means every point is computed.

The field that has the keys is lit, and so is its row; the footer says that tab moves
on (a field takes the digits and q, which elsewhere switch screens and quit).

At 80x24 the form scrolls (the buttons sit below the fold; ctrl+s submits from
anywhere). It opens on the name, the first field one types (the preset above it is a
shortcut, not a field). The axis rows have a heading row (start, stop, points, spacing)
over their inputs, in the same widths. A parameter chosen as an axis is swept: its
fixed input is disabled and shows "swept" (its value is kept and comes back when the
parameter is no longer swept), so the form never shows a value it does not use. The
λmax checkbox shows ✓ or a blank, not an X whose colour alone says on or off (nothing
under NO_COLOR).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from rich.text import Text
from textual import on, work
from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import Horizontal, VerticalScroll
from textual.message import Message
from textual.widgets import (
    Button,
    Checkbox,
    Header,
    Input,
    Label,
    Select,
    Static,
)

from core.history import HISTORIES
from core.methods import METHODS
from core.params import PARAM_NAMES, Params, friction_warnings
from slopetui.queue.local_pool import default_jobs
from slopetui.sweeps.estimate import describe, measured_speeds
from slopetui.sweeps.presets import BY_KEY, PRESETS
from slopetui.sweeps.progress import live_workers
from slopetui.sweeps.sizes import CONFIRM_ABOVE_RUNS
from slopetui.sweeps.spec import SpecError, SweepSpec, parse_spec
from slopetui.sweeps.submit import submit
from slopetui.tui.screens.base import SlopeScreen
from slopetui.tui.widgets.steady_footer import SteadyFooter

if TYPE_CHECKING:
    from slopetui.store.database import Database

DEFAULTS = Params()
AXIS_CHOICES = [(p, p) for p in PARAM_NAMES]
SPACING_CHOICES = [("linear", "linear"), ("log", "log")]
NO_AXIS = "none"
#: What a swept parameter's fixed input shows instead of its value.
SWEPT = "swept"


class OnOffCheckbox(Checkbox):
    """A checkbox whose mark says on or off without colour: Textual's ToggleButton draws
    the same X either way and only recolours it, invisible under NO_COLOR."""

    ON_MARK = "✓"
    OFF_MARK = " "
    # an initial False is no change of value, so no watcher runs: the class's mark is off
    BUTTON_INNER = OFF_MARK

    def watch_value(self) -> None:
        # an instance attribute over the class's: ToggleButton._button reads it per render
        self.BUTTON_INNER = self.ON_MARK if self.value else self.OFF_MARK
        super().watch_value()


def _axis_row(axis: str, param: str, start: str, stop: str, num: str) -> Horizontal:
    none = [("(none)", NO_AXIS)] if axis == "y" else []
    return Horizontal(
        Label(f"{axis}:", classes="row-label"),
        Select(none + AXIS_CHOICES, value=param, allow_blank=False, compact=True, id=f"{axis}-param",
               classes="axis-param"),
        Input(start, placeholder="start", compact=True, id=f"{axis}-start", classes="num"),
        Input(stop, placeholder="stop", compact=True, id=f"{axis}-stop", classes="num"),
        Input(num, placeholder="points", compact=True, id=f"{axis}-num", classes="num"),
        Select(SPACING_CHOICES, value="linear", allow_blank=False, compact=True, id=f"{axis}-spacing",
               classes="spacing"),
        classes="form-row")


def _axis_heading() -> Horizontal:
    """The headings of the axis rows' columns, in the widths of their inputs."""
    return Horizontal(
        Label("", classes="row-label"),
        Label("parameter", classes="axis-param"),
        *(Label(text, classes="heading-num") for text in ("start", "stop", "points")),
        Label("spacing", classes="spacing"),
        id="axis-heading")


def _fixed_row(names: tuple[str, ...]) -> Horizontal:
    cells: list[Any] = [Label("fixed:" if names[0] == "a" else "", classes="row-label")]
    for name in names:
        cells += [Label(name, classes="param-label"),
                  Input(f"{getattr(DEFAULTS, name):g}", compact=True, id=f"fixed-{name}",
                        classes="num")]
    return Horizontal(*cells, classes="form-row")


class NewSweepScreen(SlopeScreen[int | None]):
    """Dismissed with the new sweep's id, or None when cancelled."""

    #: Without it the scrolling form itself takes the focus, and typing goes nowhere.
    AUTO_FOCUS = "#name"
    # The heading row's own rules (the form's layout is in slopetui.tcss): one line right
    # above the x row, muted, its cells as wide as the inputs under them (Input.num: 10).
    DEFAULT_CSS = """
    NewSweepScreen #axis-heading { height: 1; }
    NewSweepScreen #axis-heading Label { color: $text-muted; text-style: italic; }
    NewSweepScreen #axis-heading .heading-num { width: 10; }
    """

    BINDINGS = [
        Binding("ctrl+s", "submit", "Submit", id="new_sweep.submit", priority=True),
        # Typed keys go into the focused field (the digits and q too): the footer says how
        # to move on, and the focused field and its row are lit (slopetui.tcss).
        Binding("tab", "app.focus_next", "Next field", id="new_sweep.next_field",
                tooltip="The next field (shift+tab: the one before)"),
        Binding("escape", "cancel", "Cancel", id="new_sweep.cancel"),
    ]

    @dataclass
    class WorkersCounted(Message):
        """The live workers (or the pool's default) and the measured speeds, for the
        estimate."""

        n: int
        speeds: dict[tuple[str, bool], float]

    @dataclass
    class Submitted(Message):
        sweep_id: int
        text: str  # what was queued, e.g. "sweep 3: 228 runs queued"

    @dataclass
    class SubmitFailed(Message):
        cause: str

    def __init__(self) -> None:
        super().__init__()
        self.spec: SweepSpec | None = None
        self.confirmed_runs = 0
        self.n_workers = 2
        #: Seconds per step measured on this store (sweeps.estimate.measured_speeds);
        #: empty until read, and for a method no run was computed with yet.
        self.speeds: dict[tuple[str, bool], float] = {}
        #: The fixed values of the swept parameters, shown again when no longer swept.
        self.unswept: dict[str, str] = {}
        #: Every field's value as the form opened (on_mount): what quitting would lose is
        #: what differs from it (``unsaved``).
        self.opened: dict[str, Any] = {}

    def compose(self) -> ComposeResult:
        yield Header()
        with VerticalScroll(id="form"):
            yield Horizontal(Label("preset:", classes="row-label"),
                             Select([(f"{p.figure}: {p.title}", p.key) for p in PRESETS], prompt="(none)",
                                    compact=True, id="preset"), classes="form-row")
            yield Horizontal(Label("name:", classes="row-label"),
                             Input(placeholder="(from the axes)", compact=True, id="name"),
                             Label("adaptive levels", classes="param-label"),
                             Input(placeholder="off", compact=True, id="adaptive-levels",
                                   classes="num"),
                             classes="form-row")
            yield _axis_heading()
            yield _axis_row("x", "k", "2", "20", "19")
            yield _axis_row("y", "tau", "0.5", "10", "12")
            yield _fixed_row(("a", "b", "c", "d"))
            yield _fixed_row(("k", "v", "tau", "delta"))
            yield Horizontal(
                Label("solver:", classes="row-label"),
                Select([(m, m) for m in METHODS], value="euler", allow_blank=False,
                       compact=True, id="solver-method", classes="spacing"),
                Label("dt", classes="param-label"), Input("0.001", compact=True, id="solver-dt", classes="num"),
                Label("t_end", classes="param-label"),
                Input("1e5", compact=True, id="solver-t_end", classes="num"),
                Label("window", classes="param-label"),
                Input("1000", compact=True, id="solver-window", classes="num"),
                OnOffCheckbox("λmax", value=True, compact=True, id="solver-lyap"),
                classes="form-row")
            yield Horizontal(
                Label("start:", classes="row-label"),
                Select([(h, h) for h in HISTORIES], value="constant", allow_blank=False,
                       compact=True, id="solver-history", classes="spacing"),
                Label("δ list", classes="param-label"),
                # short enough for the ~50 columns the field has at 80 (the rest: tooltip)
                Input(placeholder="e.g. 1e-6, 0.1: a map of where they differ",
                      compact=True, id="initial-deltas",
                      tooltip="Empty: every point from the fixed δ. A list: each lattice "
                              "point from each δ, and a map of where their regimes differ"),
                classes="form-row")
            yield Static("", id="preset-note")
            yield Static("", id="estimate")
            yield Static("", id="form-error")
            yield Static("", id="form-warnings")
            with Horizontal(id="form-buttons"):
                yield Button("Submit (ctrl+s)", variant="primary", id="submit")
                yield Button("Cancel (esc)", id="cancel")
        yield SteadyFooter()

    def on_mount(self) -> None:
        self.count_workers()
        self.validate_form()
        self.opened = self._values()  # as shown: the swept parameters' fields emptied

    def _values(self) -> dict[str, Any]:
        """Every field's value, by its id."""
        values: dict[str, Any] = {}
        values.update((w.id, w.value) for w in self.query(Input) if w.id is not None)
        values.update((w.id, w.value) for w in self.query(Select) if w.id is not None)
        values.update((w.id, w.value) for w in self.query(Checkbox) if w.id is not None)
        return values

    def unsaved(self) -> str | None:
        """What quitting now would lose, in a sentence, or None if the form is as it
        opened: the app asks before a quit (ctrl+q) that would throw away a filled form
        (slopetui.tui.app)."""
        changed = [name for name, value in self._values().items()
                   if self.opened.get(name) != value]
        if not changed:
            return None
        fields = ", ".join(name.replace("-", " ") for name in changed[:4])
        more = f" and {len(changed) - 4} more" if len(changed) > 4 else ""
        runs = f" for {self.spec.n_runs:,} runs" if self.spec is not None else ""
        return (f"The new sweep's form{runs} is not submitted: what you entered ({fields}"
                f"{more}) would be lost.")

    @work(thread=True, exclusive=True, group="new-sweep-workers")
    def count_workers(self) -> None:
        db = self.db
        if db is None:
            return
        try:
            n = len(live_workers(db)) or default_jobs()
            speeds = measured_speeds(db)
        except Exception:  # only the estimate depends on them
            return
        self.post_message(self.WorkersCounted(n, speeds))

    @on(WorkersCounted)
    def _workers_counted(self, message: WorkersCounted) -> None:
        self.n_workers, self.speeds = message.n, message.speeds
        self.validate_form()

    # --- the form as a spec mapping ----------------------------------------------------
    def _text(self, widget_id: str) -> str:
        return self.query_one(f"#{widget_id}", Input).value

    def _choice(self, widget_id: str) -> Any:
        """A select's value (never blank: the form's selects have allow_blank=False)."""
        return self.query_one(f"#{widget_id}", Select).value

    def form_data(self) -> dict[str, Any]:
        data: dict[str, Any] = {}
        if self._text("name").strip():
            data["name"] = self._text("name").strip()
        swept = set()
        for axis in ("x", "y"):
            param = self._choice(f"{axis}-param")
            if param == NO_AXIS:
                continue
            swept.add(param)
            data[axis] = {"param": param, "start": self._text(f"{axis}-start"),
                          "stop": self._text(f"{axis}-stop"), "num": self._text(f"{axis}-num"),
                          "spacing": self._choice(f"{axis}-spacing")}
        data["fixed"] = {n: self._text(f"fixed-{n}") for n in PARAM_NAMES if n not in swept}
        data["solver"] = {"method": self._choice("solver-method"), "dt": self._text("solver-dt"),
                          "t_end": self._text("solver-t_end"),
                          "window": self._text("solver-window"),
                          "lyap": self.query_one("#solver-lyap", Checkbox).value}
        data["solver"]["history"] = self._choice("solver-history")
        if self._text("adaptive-levels").strip():
            data["adaptive"] = {"levels": self._text("adaptive-levels").strip()}
        deltas = [d.strip() for d in self._text("initial-deltas").split(",") if d.strip()]
        if deltas:  # each lattice point from each delta: the map of where they differ
            data["initial"] = [{"delta": d} for d in deltas]
        return data

    def validate_form(self) -> SweepSpec | None:
        for widget in self.query(".-invalid"):
            widget.remove_class("-invalid")
        self._show_swept()
        error = self.query_one("#form-error", Static)
        try:
            # the admission checks of `slopetui submit` too (limits, characters of the name)
            spec = parse_spec(self.form_data(), submitting=True)
        except SpecError as exc:
            self.spec = None
            error.update(Text(f"✗ {exc}"))  # Text: a bracket in the input is not markup
            self._mark_invalid(exc.field)
            self.query_one("#estimate", Static).update("")
            self.query_one("#form-warnings", Static).update("")
            return None
        self.spec = spec
        error.update("")
        self.query_one("#estimate", Static).update("≈ " + describe(spec, self.n_workers, self.speeds))
        warnings = friction_warnings(spec.base)
        self.query_one("#form-warnings", Static).update(
            "\n".join(f"⚠ {w}" for w in warnings))
        return spec

    def _show_swept(self) -> None:
        """Disable the fixed input of each swept parameter (its value is not used) and
        show "swept" in it; give an input its value back once its parameter is not swept.

        Idempotent: it runs on every change, including the Input.Changed it causes. A
        value written into a swept input meanwhile (a preset) is the one kept."""
        swept = {self._choice("x-param"), self._choice("y-param")}
        for name in PARAM_NAMES:
            box = self.query_one(f"#fixed-{name}", Input)
            if name in swept:
                if box.value:  # just swept, or a preset filled it: keep the value aside
                    self.unswept[name] = box.value
                    box.value = ""
                box.placeholder = SWEPT
                box.disabled = True
            elif box.disabled:
                if not box.value:  # a preset may have filled it already
                    box.value = self.unswept.get(name, f"{getattr(DEFAULTS, name):g}")
                self.unswept.pop(name, None)
                box.placeholder = ""
                box.disabled = False

    def _mark_invalid(self, field: str) -> None:
        section, _, name = field.partition(".")
        ids = {f"{section}-{name}"}
        if section.startswith("initial"):  # initial, initial[2], initial[2].delta
            ids = {"initial-deltas"}
        if section == "adaptive":  # "adaptive" alone: a 1-D sweep cannot be adaptive
            ids = {"adaptive-levels"}
        if section in ("x", "y") and name in PARAM_NAMES:  # a bad value on the axis
            ids = {f"{section}-start", f"{section}-stop"}
        for widget_id in ids:
            for widget in self.query(f"#{widget_id}"):
                widget.add_class("-invalid")

    @on(Input.Changed)
    @on(Select.Changed)
    @on(Checkbox.Changed)
    def _changed(self, event: Input.Changed | Select.Changed | Checkbox.Changed) -> None:
        if isinstance(event, Select.Changed) and event.select.id == "preset":
            return
        self.confirmed_runs = 0
        self.validate_form()

    @on(Select.Changed, "#preset")
    def _preset(self, event: Select.Changed) -> None:
        if event.value is Select.BLANK or event.value not in BY_KEY:
            return
        preset = BY_KEY[event.value]
        spec = preset.spec
        self.query_one("#name", Input).value = spec.get("name", "")
        for axis in ("x", "y"):
            a = spec.get(axis)
            self.query_one(f"#{axis}-param", Select).value = a["param"] if a else NO_AXIS
            if a:
                for key in ("start", "stop", "num"):
                    self.query_one(f"#{axis}-{key}", Input).value = f"{a[key]:g}"
                self.query_one(f"#{axis}-spacing", Select).value = a.get("spacing", "linear")
        for name in PARAM_NAMES:
            value = spec.get("fixed", {}).get(name, getattr(DEFAULTS, name))
            self.query_one(f"#fixed-{name}", Input).value = f"{value:g}"
        solver = spec.get("solver", {})
        self.query_one("#solver-method", Select).value = solver.get("method", "euler")
        for key in ("dt", "t_end", "window"):
            if key in solver:
                self.query_one(f"#solver-{key}", Input).value = f"{solver[key]:g}"
        self.query_one("#solver-lyap", Checkbox).value = solver.get("lyap", True)
        self.query_one("#preset-note", Static).update(f"ⓘ {preset.note}")

    # --- submit ---------------------------------------------------------------------------
    @on(Button.Pressed, "#submit")
    def action_submit(self) -> None:
        spec = self.validate_form()
        if spec is None:
            self.notify("fix the field marked in red first", severity="error")
            return
        if spec.first_runs > CONFIRM_ABOVE_RUNS and self.confirmed_runs != spec.first_runs:
            self.confirmed_runs = spec.first_runs
            what = ("coarse runs" if spec.adaptive_levels is not None else "runs")
            self.query_one("#form-error", Static).update(
                f"This sweep queues {spec.first_runs} {what} (more than {CONFIRM_ABOVE_RUNS}): "
                "submit again to confirm.")
            return
        if self.db is None:
            self.notify("the database is not open yet", severity="error")
            return
        self.query_one("#submit", Button).disabled = True
        self.submit_spec(self.db, spec)

    @work(thread=True, exclusive=True, group="new-sweep-submit")
    def submit_spec(self, db: Database, spec: SweepSpec) -> None:
        try:
            out = submit(db, spec)
        except Exception as exc:  # shown in the form; nothing was written (one transaction)
            self.post_message(self.SubmitFailed(f"{type(exc).__name__}: {exc}"))
            return
        cached = f", {out.n_cached} from the cache" if out.n_cached else ""
        what = "runs" if out.adaptive_levels is None else "coarse runs (adaptive)"
        self.post_message(self.Submitted(
            out.sweep_id, f"sweep {out.sweep_id}: {out.n_runs} {what} queued{cached}"))

    @on(Submitted)
    def _submitted(self, message: Submitted) -> None:
        self.notify(message.text)
        self.dismiss(message.sweep_id)

    @on(SubmitFailed)
    def _submit_failed(self, message: SubmitFailed) -> None:
        self.query_one("#form-error", Static).update(Text(f"✗ could not submit: {message.cause}"))
        self.query_one("#submit", Button).disabled = False

    @on(Button.Pressed, "#cancel")
    def action_cancel(self) -> None:
        self.dismiss(None)
