"""The version of ioc-bench, its one source: pyproject.toml reads it, ``ioc-bench --version`` prints it."""

__version__ = "0.1.0"
