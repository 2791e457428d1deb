"""``python -m ioc_bench.cli`` is ``ioc-bench``."""

from ioc_bench.cli import main

raise SystemExit(main())
