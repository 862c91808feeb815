"""What a Database needs of a connection budget shared by several processes: the
store's side of slopetui.ops.connection_slots, which the store does not import."""

from __future__ import annotations

from typing import Protocol


class ConnectionBudget(Protocol):
    """Slots a process holds while it has a connection open (Database takes one before
    it connects and gives it back when its pool closes the connection)."""

    @property
    def held(self) -> bool:
        """This process holds a slot now."""
        ...

    def acquire(self) -> None:
        """One more connection of this process: the first takes a slot, waiting as long
        as every slot is held."""
        ...

    def release(self) -> None:
        """One connection fewer: the last gives the process's slot back."""
        ...
