"""The built-in tracks, as data: where each one's :class:`~ioc_bench.runner.protocol.Track` is.

The runner's registry (:mod:`ioc_bench.runner.tracks`) loads these on first use, by name,
as it loads installed plugins (entry-point group ``ioc_bench.tracks``): the runner imports
no track, and no track imports this list. Their order is the board's order of sections.
"""

#: Track name -> ``module:attribute`` of its :class:`~ioc_bench.runner.protocol.Track`.
BUILTIN_TRACKS = {
    "synthetic": "ioc_bench.synthetic.track:TRACK",
    "human": "ioc_bench.human.track:TRACK",
}
