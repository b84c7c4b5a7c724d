"""Shipped job configurations (TOML): ``default`` and ``paper``; see pipelines.config."""
