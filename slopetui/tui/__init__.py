"""The Textual application: ``slopetui`` with no arguments."""
