"""Shipped job configurations (TOML): ``default``, ``paper`` and ``paper-two-step``.

``paper-two-step`` reads the CSV files beside it (its measured input, a reproduction made by
benchmarks/paper_reproduction_data.py); see pipelines.config.
"""
