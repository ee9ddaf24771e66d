# tests for io (owned by the io module)
