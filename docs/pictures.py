"""Regenerate the README's pictures: the figures in docs/figures/ and the text captures of
the application in docs/screens/.

    python docs/pictures.py [--store /tmp/slopetui-pictures.db] [--only figures|screens]

On a new store it queues the two sweeps the README shows (sweep 1, the (k, tau) plane;
sweep 2, the paper's Fig. 4A) and the continuation from the Hopf point at tau = 10 (the
Branches screen's), computes them with a worker pool (about 3 minutes on two
cores, the first time), then runs the commands the README quotes: `slopetui figure` for
the figures, and the application in tmux at 80 x 24 with NO_COLOR=1 for the captures
(tmux needed). The ids the README names (sweeps 1 and 2, runs 903 and 923) are those of a
new store. Everything goes through the installed `slopetui`, as a user would run it.
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

DOCS = Path(__file__).resolve().parent
FIGURES, SCREENS = DOCS / "figures", DOCS / "screens"
SLOPETUI = [sys.executable, "-m", "slopetui"]

#: The (k, tau) plane of the README, and the shipped Fig. 4A example.
PLANE = ["--x", "k=2:20:37", "--y", "tau=0.5:10:24", "--delta", "0.1", "--method", "rk4",
         "--dt", "0.01", "--t-end", "2000", "--window", "500", "--name", "(k, tau) plane"]
#: Runs 903 (k = 10) and 923 (k = 20) of Fig. 4A on a new store.
RUN_A, RUN_B = "903", "923"
SIZE = (80, 24)
#: Seconds before a form's capture: the note a form opens with ("the form opens at run
#: 903's point") is a toast shown for 4 s (app.open_analysis), over the form's last lines.
FORM_WAIT = 6


def slopetui(*args: str, env: dict[str, str]) -> None:
    print("$ slopetui " + " ".join(args), flush=True)
    subprocess.run([*SLOPETUI, *args], env=env, check=True)


def compute(env: dict[str, str]) -> None:
    slopetui("submit", *PLANE, "--yes", env=env)
    slopetui("submit", "fig4a", "--yes", env=env)
    slopetui("continue", "--param", "k", "--from-hopf", "--tau", "10", "--to", "25", "--submit",
             env=env)
    slopetui("worker", "--exit-when-idle", env=env)


def figures(env: dict[str, str]) -> None:
    FIGURES.mkdir(exist_ok=True)
    slopetui("figure", "1", "--fold", "-o", str(FIGURES / "plane.png"), env=env)
    slopetui("figure", "2", "-o", str(FIGURES / "fig4a.png"), env=env)
    slopetui("figure", "--run", RUN_A, "-o", str(FIGURES / "run.png"), env=env)
    slopetui("figure", "--run", RUN_A, "--run", RUN_B, "-o", str(FIGURES / "compare.png"), env=env)
    for data in FIGURES.glob("*.csv"):  # the data beside each figure: not kept in git
        data.unlink()


def tmux(*args: str) -> str:
    return subprocess.run(["tmux", "-L", "slopetui-pictures", *args], check=True,
                          capture_output=True, text=True).stdout


def capture(name: str) -> None:
    text = "\n".join(line.rstrip() for line in tmux("capture-pane", "-p", "-t", "pics").splitlines())
    (SCREENS / f"{name}.txt").write_text(text.rstrip("\n") + "\n")
    print(f"captured {name}", flush=True)


def screens(env: dict[str, str]) -> None:
    """A walk through every screen at 80 x 24, colour off, as a newcomer would take it:
    the sweeps screen on the plane and on Fig. 4A, the help, the command palette, the
    new-sweep form, a run's detail (run 903: periodic, certified) with its certificate
    and the two analyses' forms it opens (an orbit at its point, a certified re-run), two
    runs compared, the queue, the SQL console, the continuations and their two forms (a
    continuation, a hysteresis sweep)."""
    if shutil.which("tmux") is None:
        raise SystemExit("the captures need tmux")
    SCREENS.mkdir(exist_ok=True)
    command = " ".join([*SLOPETUI, "--no-workers"])
    tmux("new-session", "-d", "-s", "pics", "-x", str(SIZE[0]), "-y", str(SIZE[1]),
         "-e", f"SLOPETUI_DB={env['SLOPETUI_DB']}", "-e", "NO_COLOR=1", command)
    # (capture name, keys to send first, seconds to wait before the capture)
    steps = [("sweeps-plane", ["Down"], 4), ("sweeps-fig4a", ["Up"], 3),
             ("help", ["?"], 2), ("palette", ["Escape", "C-p"], 2),
             ("new-sweep", ["Escape", "n"], 3),
             ("run-detail", ["Escape", "d", *["Right"] * 14, "Enter"], 6),
             ("run-detail-certificate", ["c"], 3),
             ("form-orbit", ["o"], FORM_WAIT), ("form-certified-rerun", ["Escape", "u"], FORM_WAIT),
             ("compare", ["Escape", "m", "Escape", *["Right"] * 20, "m", "v"], 8),
             ("queue", ["Escape", "Escape", "2"], 3),
             ("sql", ["3", "C-r"], 3), ("branches", ["Tab", "4"], 3),
             ("form-continuation", ["c"], FORM_WAIT), ("form-hysteresis", ["Escape", "h"], FORM_WAIT)]
    try:
        time.sleep(4)
        for name, keys, wait in steps:
            for key in keys:
                tmux("send-keys", "-t", "pics", key)
                time.sleep(0.4)
            time.sleep(wait)
            capture(name)
        tmux("send-keys", "-t", "pics", "Escape")
        tmux("send-keys", "-t", "pics", "C-q")
    finally:
        subprocess.run(["tmux", "-L", "slopetui-pictures", "kill-server"], capture_output=True)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--store", default="/tmp/slopetui-pictures.db",
                        help="the SQLite file to compute in (reused when it exists)")
    parser.add_argument("--only", choices=("figures", "screens"))
    args = parser.parse_args()
    env = {**os.environ, "SLOPETUI_DB": f"sqlite:///{Path(args.store).resolve()}"}
    if not Path(args.store).exists():
        compute(env)
    if args.only in (None, "figures"):
        figures(env)
    if args.only in (None, "screens"):
        screens(env)
    return 0


if __name__ == "__main__":
    sys.exit(main())
