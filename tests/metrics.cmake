# tests for metrics (owned by the metrics module)
