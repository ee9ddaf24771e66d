# tests for dec (owned by the dec module)
