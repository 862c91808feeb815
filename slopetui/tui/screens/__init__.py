"""The application's screens: sweeps, new sweep, run detail, queue, SQL console."""
