"""Where the cache is (:mod:`ioc_bench.cache`): ``$IOC_BENCH_CACHE``, else
``$XDG_CACHE_HOME/ioc-bench`` when that is an absolute path, else ``~/.cache/ioc-bench``."""

from __future__ import annotations

from pathlib import Path

import pytest

from ioc_bench.cache import cache_dir, check_cache


@pytest.fixture
def env(monkeypatch, tmp_path):
    """Neither variable set, and a home of the test's own."""
    monkeypatch.delenv("IOC_BENCH_CACHE", raising=False)
    monkeypatch.delenv("XDG_CACHE_HOME", raising=False)
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    return monkeypatch


def test_default_is_under_the_home_folder(env, tmp_path):
    assert cache_dir() == tmp_path / "home" / ".cache" / "ioc-bench"


def test_xdg_cache_home_is_used_when_set(env, tmp_path):
    env.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert cache_dir() == tmp_path / "xdg" / "ioc-bench"


@pytest.mark.parametrize("value", ["", "relative/cache", "."])
def test_an_empty_or_relative_xdg_cache_home_is_ignored(env, tmp_path, value):
    env.setenv("XDG_CACHE_HOME", value)
    assert cache_dir() == tmp_path / "home" / ".cache" / "ioc-bench"


def test_ioc_bench_cache_comes_first(env, tmp_path):
    env.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    env.setenv("IOC_BENCH_CACHE", str(tmp_path / "mine"))
    assert cache_dir() == tmp_path / "mine"
    env.setenv("IOC_BENCH_CACHE", "relative")  # taken as given, as before
    assert cache_dir() == Path("relative")


def test_an_empty_ioc_bench_cache_is_an_error_whatever_xdg_says(env, tmp_path):
    env.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    env.setenv("IOC_BENCH_CACHE", "")
    with pytest.raises(ValueError, match="IOC_BENCH_CACHE is set but empty"):
        cache_dir()


def test_check_cache_names_the_order_and_the_folder(env, tmp_path):
    a_file = tmp_path / "file"
    a_file.write_text("x")
    env.setenv("XDG_CACHE_HOME", str(a_file))
    with pytest.raises(ValueError) as exc:
        check_cache()
    message = str(exc.value)
    assert "IOC_BENCH_CACHE, else XDG_CACHE_HOME/ioc-bench, else ~/.cache/ioc-bench" in message
    assert str(a_file) in message and "\n" not in message
    env.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert check_cache() == tmp_path / "xdg" / "ioc-bench" / "demos"
    assert not (tmp_path / "xdg").exists()  # a check creates nothing
