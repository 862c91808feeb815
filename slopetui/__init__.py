"""slopetui: sweeps, storage and terminal views over the mean-field landslide model.

The numerical engine lives in the separate top-level package ``core``; this package
depends on it, never the reverse.
"""

__version__ = "0.1.0"
