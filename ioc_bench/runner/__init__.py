"""The runner: what every track's cases go through, knowing no track by name.

``protocol`` (the case, record, suite and board-section shapes a track implements),
``tracks`` (the registry tracks plug into), ``run`` (plan and run cases, resumable),
``executor``, ``process_pool`` and ``ray_executor`` (where cases run), ``results`` (result
files: atomic, checked, resumable), ``leaderboard`` (the board assembled from the tracks'
sections) and ``board_html`` (its HTML page).
"""
