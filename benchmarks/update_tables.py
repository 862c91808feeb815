"""Put the benchmarks' latest tables into docs/speed.md (the README links to it).

    python benchmarks/update_tables.py

Each benchmark that feeds the documentation writes its table with ``--markdown
benchmarks/results/<name>.md`` (bench_kernels, bench_memory, bench_tui, bench_startup, and
the end-to-end diagram, whose bench_adaptive output is kept as text). This script
replaces, in each document, the lines between ``<!-- bench:<name> -->`` and
``<!-- /bench:<name> -->`` with that file, so that the documents quote the figures the
scripts printed, never numbers typed by hand. A marker whose file is missing is left as it
is and named; a file no document marks is named too.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
RESULTS = ROOT / "benchmarks" / "results"
#: The documents with marked blocks: every table is in docs/speed.md, none in the README,
#: which stays a short getting-started page.
DOCUMENTS = (ROOT / "docs" / "speed.md",)
MARKER = re.compile(r"(<!-- bench:(?P<name>[\w-]+) -->\n)(?P<body>.*?)(<!-- /bench:(?P=name) -->)",
                    re.DOTALL)


def splice(text: str, tables: dict[str, str], used: set[str], missing: set[str]) -> str:
    """The text with every marked block replaced by its table."""
    def block(m: re.Match[str]) -> str:
        name = m["name"]
        if name not in tables:
            missing.add(name)
            return m[0]
        used.add(name)
        return f"{m[1]}{tables[name]}{m[4]}"
    return MARKER.sub(block, text)


def main() -> int:
    tables = {p.stem: p.read_text() for p in sorted(RESULTS.glob("*.md"))}
    used: set[str] = set()
    missing: set[str] = set()
    for doc in DOCUMENTS:
        text = doc.read_text()
        new = splice(text, tables, used, missing)
        if new != text:
            doc.write_text(new)
            print(f"updated {doc.relative_to(ROOT)}")
    for name in sorted(missing):
        print(f"no benchmarks/results/{name}.md: its block is left as it was", file=sys.stderr)
    for name in sorted(set(tables) - used):
        print(f"benchmarks/results/{name}.md is marked in no document", file=sys.stderr)
    return 1 if missing else 0


if __name__ == "__main__":
    sys.exit(main())
