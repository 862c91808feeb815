"""A sweep's name, note and tags as the faces change them (``slopetui rename``, ``note``,
``tag``; the application's sweep actions): what each may hold, checked before the store
(``slopetui.store.sweeps.annotations``) writes it.

- a name: printable text, 1 to MAX_NAME characters (as a spec's name: it is one line of
  ``status`` and of the application);
- a note: printable text and line breaks, at most MAX_NOTE characters;
- a tag: TAG_FORM, compared as typed in lower case ("Paper" is "paper"), so that
  ``runs --tag paper`` finds what ``tag 3 Paper`` tagged.

Control characters are refused (they would drive the terminals the text is shown on);
what is stored is still escaped wherever it is shown (``slopetui.display_text``). Every
error is a LabelError naming the field and the allowed form.
"""

from __future__ import annotations

import re
from collections.abc import Iterable

from slopetui.display_text import unsafe_characters
from slopetui.store.database import Database
from slopetui.store.sweeps import annotations as stored
from slopetui.store.sweeps.annotations import SweepLabels
from slopetui.sweeps.control import UnknownSweep

__all__ = ["MAX_NAME", "MAX_NOTE", "TAG_FORM", "LabelError", "SweepLabels", "add_tags",
           "change_tags", "check_tag", "labels", "remove_tags", "rename", "set_note"]

#: Longest sweep name (characters): slopetui.sweeps.spec.MAX_NAME, which a submitted name
#: keeps to; not imported from there, which loads numpy (``slopetui runs --tag`` and
#: ``tag`` would pay 0.1 s for it). tests/unit/test_annotations.py checks they agree.
MAX_NAME = 200
#: Longest note (characters): a few paragraphs, shown whole under a sweep.
MAX_NOTE = 2000
#: What a tag is: a word a shell passes unquoted and a filter names exactly.
TAG_PATTERN = re.compile(r"[a-z0-9][a-z0-9._-]{0,31}")
TAG_FORM = ("1 to 32 letters, digits, '.', '_' or '-', starting with a letter or a digit "
            "(e.g. fig4, paper-v2)")


class LabelError(ValueError):
    """A name, note or tag that may not be stored: ``field`` is which, the message says
    what is allowed (one line, as a spec's errors)."""

    def __init__(self, field: str, message: str) -> None:
        super().__init__(f"{field}: {message}")
        self.field = field


def check_tag(text: str, field: str = "tag") -> str:
    """The tag as stored (lower case), or a LabelError naming ``field`` and TAG_FORM."""
    tag = text.strip().lower()
    if TAG_PATTERN.fullmatch(tag) is None:
        raise LabelError(field, f"{text!r} is not a tag: allowed {TAG_FORM}")
    return tag


def check_name(text: str) -> str:
    """The name as stored (surrounding blanks removed), or a LabelError naming ``name``."""
    name = text.strip()
    if not name or len(name) > MAX_NAME:
        raise LabelError("name", f"expected 1 to {MAX_NAME} characters, got {len(name)}")
    _printable("name", name, "printable text")
    return name


def check_note(text: str) -> str | None:
    """The note as stored (None when blank: no note), or a LabelError naming ``note``."""
    note = text.strip()
    if len(note) > MAX_NOTE:
        raise LabelError("note", f"expected at most {MAX_NOTE} characters, got {len(note)}")
    _printable("note", note.replace("\n", ""), "printable text and line breaks")
    return note or None


def _printable(field: str, text: str, allowed: str) -> None:
    bad = unsafe_characters(text)
    if bad:
        raise LabelError(field, f"control characters are not allowed ({', '.join(bad)}): "
                               f"allowed {allowed}")


def labels(db: Database, sweep_id: int) -> SweepLabels:
    """The sweep's name, note and tags; UnknownSweep if the store has no such sweep."""
    found = stored.labels_of(db, [sweep_id]).get(sweep_id)
    if found is None:
        raise UnknownSweep(sweep_id)
    return found


def rename(db: Database, sweep_id: int, name: str) -> str:
    """Rename the sweep; the name stored. LabelError, UnknownSweep."""
    name = check_name(name)
    if not stored.rename(db, sweep_id, name):
        raise UnknownSweep(sweep_id)
    return name


def set_note(db: Database, sweep_id: int, note: str) -> str | None:
    """Replace the sweep's note (blank: remove it); the note stored. LabelError,
    UnknownSweep."""
    checked = check_note(note)
    if not stored.set_note(db, sweep_id, checked):
        raise UnknownSweep(sweep_id)
    return checked


def change_tags(db: Database, sweep_id: int, add: Iterable[str] = (),
                remove: Iterable[str] = ()) -> tuple[str, ...]:
    """Add and remove tags of the sweep in one transaction (a tag both added and removed
    is removed); its tags after. LabelError (nothing is written), UnknownSweep."""
    adding = [check_tag(t) for t in add]
    removing = [check_tag(t) for t in remove]
    after = stored.change_tags(db, sweep_id, set(adding) - set(removing), removing)
    if after is None:
        raise UnknownSweep(sweep_id)
    return after


def add_tags(db: Database, sweep_id: int, tags: Iterable[str]) -> tuple[str, ...]:
    """Tag the sweep; its tags after. LabelError (nothing is written), UnknownSweep."""
    return change_tags(db, sweep_id, add=tags)


def remove_tags(db: Database, sweep_id: int, tags: Iterable[str]) -> tuple[str, ...]:
    """Remove these tags from the sweep; its tags after. LabelError, UnknownSweep."""
    return change_tags(db, sweep_id, remove=tags)
