"""A lattice of labelled points in terminal cells, as the application's phase grid draws
it (slopetui.tui.widgets.phase_grid): blocks of points where the lattice is larger than
the room, and with colour two rows of blocks per character, in half blocks.

Labels are style keys (regime_colors.LEGEND_ORDER) coded as small integers (``CODES``) in
a (ny, nx) array indexed [iy, ix]: iy = 0 is the lattice's lowest row, drawn at the
bottom.

*Blocks.* A block of sx x sy points shows its most common finished label (pending only
when none of its points has finished): a rare regime stays visible where it is the
only result, and a live sweep's finished runs show before their neighbours'. Ties go
to the label first in LEGEND_ORDER.

*Half blocks.* A character holds two blocks, one above the other: the upper half block
``▀`` in the upper one's colour over a background of the lower one's, so a terminal of
120 x 40 draws a 100 x 100 lattice as 100 columns by 50 rows of characters. Two equal
halves are a blank in that colour, one empty half (above the top row of an odd count) the
other half alone (``▄``). Neighbouring characters of the same colours are one run of
text, one style: a phase diagram is mostly large regions, and every style costs the
terminal's renderer the same whether it covers one character or fifty.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from slopetui.plots.regime_colors import LEGEND_ORDER, PENDING

#: Each style key's code in a lattice array.
CODES: Mapping[str, int] = {key: i for i, key in enumerate(LEGEND_ORDER)}
PENDING_CODE = CODES[PENDING]
UPPER, LOWER, FULL = "▀", "▄", " "

#: A run of characters of one style: text, foreground, background (None: the terminal's).
Run = tuple[str, str | None, str | None]


def lattice_codes(labels: Mapping[tuple[int, int], str | None], nx: int, ny: int) -> np.ndarray:
    """The (ny, nx) code array of the labels by (ix, iy): None, and points without a
    label, pending."""
    codes = np.full((ny, nx), PENDING_CODE, dtype=np.int8)
    for (ix, iy), label in labels.items():
        if label is not None:
            codes[iy, ix] = CODES[label]
    return codes


def _blocks(array: np.ndarray, sx: int, sy: int, fill: object) -> np.ndarray:
    """The array padded with ``fill`` to whole blocks, as (rows, cols, sy * sx)."""
    ny, nx = array.shape
    rows, cols = -(-ny // sy), -(-nx // sx)
    padded = np.full((rows * sy, cols * sx), fill, dtype=array.dtype)
    padded[:ny, :nx] = array
    return padded.reshape(rows, sy, cols, sx).transpose(0, 2, 1, 3).reshape(rows, cols, sy * sx)


def block_labels(codes: np.ndarray, sx: int, sy: int) -> np.ndarray:
    """Per block of sx x sy points (the last ones may be partial), the code it shows: its
    most common finished label, pending if none finished (module docstring)."""
    if sx == sy == 1:
        return codes
    blocks = _blocks(codes, sx, sy, PENDING_CODE)
    counts = (blocks[..., None] == np.arange(len(CODES))).sum(axis=2)
    counts[..., PENDING_CODE] = 0
    return np.where(counts.any(axis=2), counts.argmax(axis=2), PENDING_CODE).astype(np.int8)


def all_in_blocks(mask: np.ndarray, sx: int, sy: int) -> np.ndarray:
    """Per block, whether the mask holds for every point of it (a partial block: for its
    points)."""
    if sx == sy == 1:
        return mask
    return np.asarray(_blocks(mask, sx, sy, True).all(axis=2))


def half_blocks(pixels: Sequence[Sequence[str | None]]) -> list[list[Run]]:
    """Rows of colours (top first; None: nothing there) as rows of characters, two rows of
    colours each (an odd count: an empty row above the first), each a list of runs of
    one style (module docstring)."""
    rows = [list(row) for row in pixels]
    if len(rows) % 2:
        rows.insert(0, [None] * (len(rows[0]) if rows else 0))
    out = []
    for upper, lower in zip(rows[::2], rows[1::2], strict=True):
        runs: list[Run] = []
        for top, bottom in zip(upper, lower, strict=True):
            if top == bottom:
                cell: Run = (FULL, None, top)
            elif top is None:
                cell = (LOWER, bottom, None)
            elif bottom is None:
                cell = (UPPER, top, None)
            else:
                cell = (UPPER, top, bottom)
            if runs and runs[-1][1:] == cell[1:]:
                runs[-1] = (runs[-1][0] + cell[0], cell[1], cell[2])
            else:
                runs.append(cell)
        out.append(runs)
    return out
