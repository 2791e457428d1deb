"""Old names kept for plugin authors' scripts (``docs/plugin_api.md``).

The package ``bench`` was split: the runner is :mod:`ioc_bench.runner`, the synthetic track
:mod:`ioc_bench.synthetic`. Only :mod:`ioc_bench.bench.observe` stays, the one of its modules
the plugin API documented; new code imports :mod:`ioc_bench.synthetic.observe`.
"""
