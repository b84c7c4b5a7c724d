"""Example parameter files of the statmodel package (package data: *.toml)."""
