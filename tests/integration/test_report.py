"""The report end to end: `slopetui reproduce --report` queues every figure, computes it
with a real worker pool (-j 2) and writes the document (the presets and an interrupted
report, in one process: tests/unit/test_reproduce.py)."""

from __future__ import annotations

from slopetui.cli import main


def test_the_report_runs_end_to_end(tmp_path, capsys):
    out = tmp_path / "docs" / "reproduction.md"
    code = main(["reproduce", "--report", "--resolution", "2", "--t-end", "100", "-j", "2",
                 "--no-orbits", "--out", str(out), "--db", f"sqlite:///{tmp_path / 's.db'}"])
    assert code == 0
    text = out.read_text()
    for figure in ("Fig. 2A", "Fig. 3", "Fig. 4A", "Fig. 4B", "Fig. 4C", "Fig. 5A", "Fig. 6B",
                   "Fig. 7A", "Fig. 8B", "Fig. 9A", "Fig. 10B"):
        assert figure in text
    assert text.count("**Verdict: ") == 11
    assert "**The paper says:**" in text and "```text" in text
