"""Runs: their claims as jobs (a batch claimed, begun, completed), the result cache, the
workers' measured speeds, the initial states histories name, and the notebooks' frames.
"""
