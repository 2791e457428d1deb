"""Plots (matplotlib, headless). Every function writes its figure atomically and returns the path."""
