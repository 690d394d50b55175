"""Benchmarks: `python -m benchmarks [--json]` prints ratios, never asserts wall time."""
