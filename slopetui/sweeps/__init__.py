"""Sweeps: their specs (TOML or flags), their expansion into runs, and their progress."""
