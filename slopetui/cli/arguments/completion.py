"""The arguments of ``slopetui completion``."""

from __future__ import annotations

import argparse

#: The shells argcomplete writes code for.
SHELLS = ("bash", "zsh", "fish", "tcsh", "powershell")

INSTALL = """\
Install it once, in your shell's start-up file:
  bash  (~/.bashrc):   eval "$(slopetui completion bash)"
  zsh   (~/.zshrc, after compinit):   eval "$(slopetui completion zsh)"
  fish  (~/.config/fish/config.fish):   slopetui completion fish | source
then open a new shell. `slopetui show <TAB>` lists the sweep ids (zsh and fish with
their names), `slopetui continue --from-run <TAB>` the newest run ids."""


def declare(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("completion", help="print the shell code that completes slopetui's "
                                          "commands, options and sweep or run ids",
                       description="Print the code that makes SHELL complete slopetui's "
                                   "subcommands, options,\nand the sweep and run ids of the "
                                   "store (with argcomplete).",
                       epilog=INSTALL, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("shell", choices=SHELLS, metavar="SHELL",
                   help="one of " + ", ".join(SHELLS))
