"""Sweeps: their rows written (a sweep with its runs, pause, resume, cancel, delete), the
reads behind their progress, and an adaptive sweep's refinement.
"""
