# tests for cli (owned by the cli module)
