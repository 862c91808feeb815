"""``slopetui compare A B``: two sweeps' specs side by side (slopetui.sweeps.spec_compare),
the settings that differ marked."""

from __future__ import annotations

import argparse
from typing import Any

from slopetui.cli.options import open_db, sweep_arg
from slopetui.display_text import terminal_safe
from slopetui.json_text import json_text
from slopetui.sweeps.spec_compare import SettingPair, compare_specs

#: The widest a value column gets (characters); a longer value (a list of initial
#: conditions) is cut with "…" in the table, never in --json.
VALUE_WIDTH = 32


def _cut(text: str) -> str:
    return text if len(text) <= VALUE_WIDTH else text[:VALUE_WIDTH - 1] + "…"


def _json_setting(s: SettingPair) -> dict[str, Any]:
    """A setting in --json: each side's stored value as stored (a number as the spec holds
    it, not as the table prints it), a side without the setting left out."""
    out: dict[str, Any] = {"key": s.key}
    if s.a_present:
        out["a"] = s.a_value
    if s.b_present:
        out["b"] = s.b_value
    out["differs"] = s.differs
    return out


def handle(args: argparse.Namespace) -> int:
    a, b = sweep_arg(args.a, "SWEEP_A"), sweep_arg(args.b, "SWEEP_B")
    found = compare_specs(open_db(args), a, b)
    settings = found.differences if args.differences else found.settings
    if args.json:
        print(json_text({"a": {"id": a, "name": found.a.name}, "b": {"id": b, "name": found.b.name},
                         "settings": [_json_setting(s) for s in settings]}))
        return 0
    # a spec's keys are stored text too (another tool may have written them): escaped
    # before the widths are measured
    rows = [(terminal_safe(s.key), _cut(terminal_safe(s.a)), _cut(terminal_safe(s.b)), s.differs)
            for s in settings]
    titles = (f"sweep {a}", f"sweep {b}")
    wk = max([len("setting"), *(len(r[0]) for r in rows)])
    wa = max([len(titles[0]), *(len(r[1]) for r in rows)])
    print(f"  {'setting':{wk}}  {titles[0]:{wa}}  {titles[1]}")
    print(f"  {'name':{wk}}  {_cut(terminal_safe(found.a.name)):{wa}}  "
          f"{_cut(terminal_safe(found.b.name))}")
    for key, va, vb, differs in rows:
        print(f"{'*' if differs else ' '} {key:{wk}}  {va:{wa}}  {vb}".rstrip())
    n = len(found.differences)
    print(f"({n} of {len(found.settings)} setting{'s' if len(found.settings) != 1 else ''} "
          f"differ{'s' if n == 1 else ''})")
    return 0
