"""The paper reproduced: measurements on the preset sweeps, verdicts, and the report."""
