"""Shipped job configurations (TOML): ``default``, ``paper`` and ``paper-two-step`` (with its CSV files); see pipelines.config."""
