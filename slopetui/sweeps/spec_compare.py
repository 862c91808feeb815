"""Two sweeps' specs side by side (``slopetui compare A B``, the application's compare
of two sweeps): every setting of either spec as a dotted key (``x.param``,
``fixed.tau``, ``solver.dt``), its value in each, and whether they differ.

Specs are compared as stored (as submitted, after validation: ``SweepSpec.to_dict``), so a
default the spec did not name reads as absent ("-") on that side; the sweep's name is not
part of its spec here (the caller shows it as the column's title). Whether a setting differs
is decided on the stored values, never on their text: 10.000001 and 10.000004 differ even
where a short format would print both as 10; 5 and 5.0 are the same number.
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
    differ, and each side's stored value (``a_value``/``b_value``; ``a_present``/``b_present``
    False where that spec does not name the setting)."""

    key: str
    a: str
    b: str
    differs: bool
    a_value: Any = None
    b_value: Any = None
    a_present: bool = True
    b_present: bool = True


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
    """A setting as text: a number by its shortest text that reads back as the same float
    (5.0 and 5 both read 5; 10.000001 keeps every digit), lists as compact JSON."""
    if value is None:
        return "none"
    if isinstance(value, bool):
        return str(value).lower()
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return str(int(value)) if value.is_integer() else repr(value)
    if isinstance(value, (list, tuple, dict)):
        return json.dumps(value, separators=(",", ":"), default=str)
    return str(value)


def compare_specs(db: Database, a: int, b: int) -> SpecComparison:
    """The specs of sweeps a and b, setting by setting in key order, the name left out.
    UnknownSweep for an id the store does not hold, naming its argument (SWEEP_A or
    SWEEP_B, as ``slopetui compare`` calls them)."""
    found = specs_of(db, [a, b])
    for sweep_id, field in ((a, "SWEEP_A"), (b, "SWEEP_B")):
        if sweep_id not in found:
            raise UnknownSweep(sweep_id, field)
    left, right = (flat({k: v for k, v in found[i].spec.items() if k != "name"}) for i in (a, b))
    settings = []
    for key in sorted(left.keys() | right.keys()):
        ta = value_text(left[key]) if key in left else ABSENT
        tb = value_text(right[key]) if key in right else ABSENT
        differs = key not in left or key not in right or not same_value(left[key], right[key])
        settings.append(SettingPair(key, ta, tb, differs, left.get(key), right.get(key),
                                    key in left, key in right))
    return SpecComparison(found[a], found[b], tuple(settings))


def same_value(x: Any, y: Any) -> bool:
    """Whether two stored settings are the same: numbers by value (5 and 5.0 alike), a
    boolean only with a boolean (true is not the number 1), lists and maps item by item,
    anything else by equality and type."""
    if isinstance(x, bool) or isinstance(y, bool):
        return isinstance(x, bool) and isinstance(y, bool) and x == y
    if isinstance(x, (int, float)) and isinstance(y, (int, float)):
        return x == y
    if isinstance(x, (list, tuple)) and isinstance(y, (list, tuple)):
        return len(x) == len(y) and all(same_value(u, v) for u, v in zip(x, y, strict=True))
    if isinstance(x, dict) and isinstance(y, dict):
        return x.keys() == y.keys() and all(same_value(x[k], y[k]) for k in x)
    return type(x) is type(y) and x == y
