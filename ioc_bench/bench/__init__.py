"""The benchmark: robustness conditions, demonstrations, cases, scores."""
