"""Stored text made safe to show on a terminal, and the characters a new name may not hold.

Sweep names, statuses, regimes and worker ids are text from a shared store: another
user, an older slopetui or another tool may have written anything there. Printed raw, an
ESC (``\\x1b[...``) or a C1 CSI (``\\x9b``) drives the reader's terminal (colours, cursor,
window title, on some terminals clipboard writes), and a bidi override (U+202E) makes
text read backwards. So every place that shows stored text shows it through
``terminal_safe``, and submissions are refused when ``unsafe_characters`` finds any.

Both use one definition, ``is_unsafe``: the control characters of Unicode category Cc
(C0, DEL, C1; tab and newline included, since names are one line), the bidi embedding,
override and isolate controls (U+202A-U+202E, U+2066-U+2069), the directional marks
U+200E, U+200F and U+061C, and the line and paragraph separators U+2028, U+2029 (some
terminals and Textual break lines on them). An unsafe character is shown as a visible
escape, ``\\x1b`` or ``\\u202e``, so that the reader sees it is there.
"""

from __future__ import annotations

import re
import unicodedata
from typing import Protocol, TextIO

#: Bidi controls that reorder the text after them (embeddings, overrides, isolates, marks).
BIDI_CONTROLS = frozenset(
    [chr(c) for c in range(0x202A, 0x202F)] + [chr(c) for c in range(0x2066, 0x206A)]
    + ["\u200e", "\u200f", "\u061c"])
#: Line and paragraph separators: a line break to some renderers.
LINE_SEPARATORS = frozenset("\u2028\u2029")


def is_unsafe(ch: str) -> bool:
    """True for a character that must not reach a terminal raw (see the module doc)."""
    return unicodedata.category(ch) == "Cc" or ch in BIDI_CONTROLS or ch in LINE_SEPARATORS


#: ``is_unsafe`` as one character class (category Cc is exactly U+0000-U+001F and
#: U+007F-U+009F; tests/unit/test_input_names.py holds the two equal). ``slopetui sql``
#: and the console escape every cell: text for 1000 rows of 10 columns took 1.3 ms
#: unescaped, 12.7 ms escaped by a loop over the characters, 1.9 ms by this regex.
UNSAFE = re.compile("[\x00-\x1f\x7f-\x9f" + "".join(sorted(BIDI_CONTROLS | LINE_SEPARATORS))
                    + "]")


def escape_char(ch: str) -> str:
    """The visible escape of one character: ``\\x1b``, ``\\u202e``."""
    code = ord(ch)
    return f"\\x{code:02x}" if code < 0x100 else f"\\u{code:04x}"


def terminal_safe(text: object) -> str:
    """``text`` (any object; None gives "") with every unsafe character escaped.

    Plain text stays as it is, so a name reads the same as before; the cost is a scan of
    the string (names are at most a few hundred characters).
    """
    s = "" if text is None else str(text)
    if UNSAFE.search(s) is None:
        return s
    return UNSAFE.sub(lambda m: escape_char(m.group(0)), s)


def unsafe_characters(text: str) -> list[str]:
    """The distinct unsafe characters of ``text``, escaped, in order of appearance."""
    seen: list[str] = []
    for ch in text:
        if is_unsafe(ch) and escape_char(ch) not in seen:
            seen.append(escape_char(ch))
    return seen


def terminal_safe_lines(text: str) -> str:
    """``text`` of several lines (a CSV for a terminal) made safe, its newlines kept."""
    return "\n".join(terminal_safe(line) for line in text.split("\n"))


class TextOut(Protocol):
    """What a writer of rows needs of its output: a text stream, or TerminalSafeWriter."""

    def write(self, text: str, /) -> int: ...

    def flush(self) -> None: ...


class TerminalSafeWriter:
    """A text stream that escapes what is written to it (``terminal_safe_lines``): for
    data written on the fly (``csv.writer``) to a terminal. Into a file or a pipe, data
    goes raw instead: a reader there must get what the store holds (``for_terminal``)."""

    def __init__(self, out: TextIO) -> None:
        self.out = out

    def write(self, text: str) -> int:
        return self.out.write(terminal_safe_lines(text))

    def flush(self) -> None:
        self.out.flush()


def for_terminal(out: TextIO) -> TextOut:
    """``out`` itself into a file or a pipe; escaped (TerminalSafeWriter) on a terminal."""
    return TerminalSafeWriter(out) if out.isatty() else out
