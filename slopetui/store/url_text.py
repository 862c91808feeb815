"""A database URL as a message shows it: its password hidden.

``Database.display_url`` hides the password of a URL that SQLAlchemy parsed. A URL it
cannot parse (a typo) is quoted by the message that refuses it, so that the user sees
what is wrong, and the password in it must not reach the terminal, a log or a screen
shared with others either. Light on purpose (no SQLAlchemy), like
slopetui.store.location.
"""

from __future__ import annotations

import re

#: What stands for a password in messages (SQLAlchemy's render_as_string does the same).
HIDDEN = "***"
#: A password given in the query (``?password=...``: libpq and psycopg take it there too),
#: which SQLAlchemy's hide_password leaves as it is.
_QUERY_PASSWORD = re.compile(r"([?&]password=)[^&#]*", re.IGNORECASE)


def password_hidden(text: str) -> str:
    """``text``, a URL or a typo of one, with everything from the first ``:`` after the
    scheme's ``://`` (or the start) to the last ``@`` replaced by ``***``:
    ``postgresql://u:***@host/db``. A password may hold ``@``, ``:`` or ``/`` unescaped in
    a typo, so this hides too much rather than too little (an ``@`` in a query hides the
    host too); a ``password=`` in the query is hidden too (``?password=***``); a text
    without either is returned as it is."""
    text = _QUERY_PASSWORD.sub(rf"\g<1>{HIDDEN}", text)
    scheme_end = text.find("://")
    start = 0 if scheme_end < 0 else scheme_end + 3
    at = text.rfind("@", start)
    colon = text.find(":", start, at)
    if at < 0 or colon < 0:
        return text
    return f"{text[:colon + 1]}{HIDDEN}{text[at:]}"


def holds_password(text: str) -> bool:
    """Whether ``text`` (a URL as typed) carries a password: what ``password_hidden`` hides."""
    return password_hidden(text) != text
