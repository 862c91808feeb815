"""CI: start the application headless on a new store and wait for its first screen.

Run by the python of a plain `pip install .` venv, outside the checkout, so that it
proves the installed package (textual included) draws the application.
"""

from __future__ import annotations

import asyncio
import sys

from slopetui.tui.app import SlopeApp
from slopetui.tui.screens.sweeps import SweepsScreen


async def first_screen(db_url: str) -> str:
    app = SlopeApp(db_url, start_workers=False)
    async with app.run_test(size=(80, 24)) as pilot:
        for _ in range(100):  # the store opens in a thread worker; up to 10 s
            await pilot.pause(0.1)
            if app.db is not None and isinstance(app.screen, SweepsScreen):
                break
        else:
            raise SystemExit(f"no first screen after 10 s: {app.screen!r}")
        return app.export_screenshot()


if __name__ == "__main__":
    svg = asyncio.run(first_screen(sys.argv[1]))
    assert "slopetui" in svg, "the first screen has no title"
    print(f"TUI first screen drawn ({len(svg)} bytes of SVG)")
