"""The durable job queue (runs with a status, claimed under a lease) and the worker pool."""
