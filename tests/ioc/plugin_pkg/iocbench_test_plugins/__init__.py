"""Plugins written to each earlier shape of the ioc-bench plugin API (see pyproject.toml)."""
