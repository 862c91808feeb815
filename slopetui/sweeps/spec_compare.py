"""Two sweeps' specs side by side (``slopetui compare A B``, the application's compare
of two sweeps): every setting of either spec as a dotted key (``x.param``,
``fixed.tau``, ``solver.dt``), its value in each, and whether they differ.

Specs are compared as stored (as submitted, after validation: ``SweepSpec.to_dict``), so a
default the spec did not name reads as absent ("-") on that side; the sweep's name is not
part of its spec here (the caller shows it as the column's title).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import Any

from slopetui.store.database import Database
from slopetui.store.sweeps.annotations import SpecOfSweep, specs_of
from slopetui.sweeps.control import UnknownSweep

#: What a side shows for a setting its spec does not have.
ABSENT = "-"


@dataclass(frozen=True)
class SettingPair:
    """One setting of two specs: its dotted key, each side's value as text, whether they
    differ."""

    key: str
    a: str
    b: str
    differs: bool


@dataclass(frozen=True)
class SpecComparison:
    a: SpecOfSweep
    b: SpecOfSweep
    settings: tuple[SettingPair, ...]

    @property
    def differences(self) -> tuple[SettingPair, ...]:
        return tuple(s for s in self.settings if s.differs)


def flat(spec: dict[str, Any], prefix: str = "") -> dict[str, Any]:
    """The spec's settings by dotted key; a list (initial conditions, a δ list) is one
    value."""
    out: dict[str, Any] = {}
    for key, value in spec.items():
        if isinstance(value, dict):
            out.update(flat(value, f"{prefix}{key}."))
        else:
            out[f"{prefix}{key}"] = value
    return out


def value_text(value: Any) -> str:
    """A setting as text: numbers by :g (5.0 and 5 read alike), lists as compact JSON."""
    if value is None:
        return "none"
    if isinstance(value, bool):
        return str(value).lower()
    if isinstance(value, (int, float)):
        return f"{value:g}"
    if isinstance(value, (list, tuple, dict)):
        return json.dumps(value, separators=(",", ":"), default=str)
    return str(value)


def compare_specs(db: Database, a: int, b: int) -> SpecComparison:
    """The specs of sweeps a and b, setting by setting in key order, the name left out.
    UnknownSweep for an id the store does not hold."""
    found = specs_of(db, [a, b])
    for sweep_id in (a, b):
        if sweep_id not in found:
            raise UnknownSweep(sweep_id)
    left, right = (flat({k: v for k, v in found[i].spec.items() if k != "name"}) for i in (a, b))
    settings = []
    for key in sorted(left.keys() | right.keys()):
        ta = value_text(left[key]) if key in left else ABSENT
        tb = value_text(right[key]) if key in right else ABSENT
        settings.append(SettingPair(key, ta, tb, ta != tb))
    return SpecComparison(found[a], found[b], tuple(settings))
